//! `fenestra render` and `fenestra reference`.

use crate::{progress::Bar, scene_arg};
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use fenestra_core::image::Image;
use fenestra_core::mis::MisHeuristic;
use fenestra_eval::hash::debug_hash;
use fenestra_eval::metrics;
use fenestra_render::integrator::{self, IntegratorOptions};
use fenestra_render::portal::{PortalChoice, PortalSampling, Portals};
use fenestra_render::{
    output, Film, LightSelection, RenderControl, RenderScene, RenderSettings, RenderStats,
};
use fenestra_scene::{Backend, Scene};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

#[derive(Clone, Copy, ValueEnum, Debug)]
enum Mis {
    Balance,
    Power,
}

/// What is rendered and how: shared by `render` and `reference`.
#[derive(Args)]
pub struct RenderOpts {
    /// builtin:NAME (see `fenestra list`), a pbrt-v4 scene file, or an OBJ/PLY mesh.
    scene: String,
    #[command(flatten)]
    scene_options: scene_arg::SceneOptions,
    /// Integrator: hf (BSDF sampling), af_hf (light and BSDF sampling with MIS) or lp_hf
    /// (light-portal and BSDF sampling with MIS).
    #[arg(long, default_value = "af_hf")]
    integrator: String,
    /// Light portals for lp_hf: a portals.json file, or "auto" to estimate them first with
    /// the default parameters of `fenestra portals` (default: the scene's own portals).
    #[arg(long)]
    portals: Option<String>,
    /// lp_hf: how a point is chosen on a portal: solid-angle (rectangles by the solid angle
    /// they subtend, Urena et al. 2013) or area (seed 000 eq. 4.1).
    #[arg(long, default_value = "solid-angle")]
    portal_sampling: PortalSampling,
    /// lp_hf: how a portal is picked: contribution (solid angle times cosine at the point),
    /// facing (uniform among those not behind the surface, as Cycles) or uniform (the seed's).
    #[arg(long, default_value = "contribution")]
    portal_choice: PortalChoice,
    /// lp_hf: probability that a sample comes from light sampling instead of the portals
    /// (Cycles mixes its portals with environment sampling; 0 uses the portals only).
    #[arg(long, default_value_t = 0.0)]
    portal_light_mix: f32,
    /// With --portals auto: the shape fitted to each cluster (smallest, ellipse, rectangle
    /// or pca; see `fenestra portals --model`).
    #[arg(long, default_value = "smallest")]
    portal_model: fenestra_portals::estimate::Model,
    /// Samples per pixel (default: the scene's).
    #[arg(long)]
    spp: Option<u32>,
    /// Maximum path length in segments from the camera to the emitter (2 = direct light only).
    #[arg(long)]
    max_depth: Option<u32>,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Image size as WxH (default: the scene's).
    #[arg(long)]
    resolution: Option<String>,
    /// MIS heuristic for af_hf.
    #[arg(long, value_enum, default_value = "power")]
    mis: Mis,
    /// Exponent of the power heuristic.
    #[arg(long, default_value_t = 2.0)]
    beta: f32,
    /// Path length from which Russian roulette may end paths.
    #[arg(long, default_value_t = 3)]
    rr_depth: u32,
    /// How next-event estimation picks a light.
    #[arg(long, default_value = "power")]
    light_selection: LightSelection,
    /// Ray-query backend: embree or obvhs.
    #[arg(long)]
    bvh: Option<Backend>,
    /// PNG exposure in stops (default: automatic, log-average luminance to middle grey).
    #[arg(long, allow_negative_numbers = true)]
    exposure: Option<f32>,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    opts: RenderOpts,
    /// Render for this many seconds instead of a fixed sample count (with --spp: whichever
    /// comes first).
    #[arg(long, allow_negative_numbers = true)]
    time: Option<f64>,
    /// A reference image: the sidecar then records MSE and relative MSE after every pass
    /// (the convergence curve).
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Stop once the relative MSE against --reference falls to this value.
    #[arg(long, requires = "reference")]
    target_rel_mse: Option<f64>,
    /// Also write OUT.var.exr, the per-pixel variance of the mean.
    #[arg(long)]
    variance: bool,
    /// Output EXR; the PNG and JSON sidecar are written beside it.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Args)]
pub struct ReferenceArgs {
    #[command(flatten)]
    opts: RenderOpts,
    /// Folder of cached references, keyed by scene content, settings and resolution.
    #[arg(long, default_value = "refs")]
    cache: PathBuf,
}

fn parse_resolution(s: &str) -> Result<(u32, u32)> {
    let bad = || {
        anyhow::anyhow!("bad resolution '{s}': expected WxH with positive integers, e.g. 512x512")
    };
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    if w == 0 || h == 0 || w > 65536 || h > 65536 {
        bail!(bad());
    }
    // The film keeps 56 bytes per pixel (sums and squares in f64, a count).
    if w as u64 * h as u64 > 1 << 28 {
        bail!("resolution {w}x{h} is too large: at most 268 million pixels (about 15 GB of film)");
    }
    Ok((w, h))
}

/// A render fully specified and checked, ready to run.
struct Job {
    desc: fenestra_scene::SceneDesc,
    width: u32,
    height: u32,
    /// `None` for lp_hf with `--portals auto`: made once the scene is built and its portals
    /// estimated.
    integrator: Option<Box<dyn integrator::Integrator>>,
    /// Kept for the reference cache key.
    options: IntegratorOptions,
    settings: RenderSettings,
}

impl RenderOpts {
    /// Checks every argument before the (possibly long) scene build.
    fn job(&self, time: Option<f64>) -> Result<Job> {
        let resolution = self
            .resolution
            .as_deref()
            .map(parse_resolution)
            .transpose()?;
        if let Some(t) = time {
            if !(t.is_finite() && t > 0.0) {
                bail!("--time must be a positive number of seconds, got {t}");
            }
        }
        if self.spp == Some(0) {
            bail!("--spp must be at least 1");
        }
        if self.max_depth == Some(0) {
            bail!("--max-depth must be at least 1 (1 = emitters seen directly, 2 = direct light)");
        }
        if !(0.0..=1.0).contains(&self.portal_light_mix) {
            bail!(
                "--portal-light-mix must lie in [0, 1], got {}",
                self.portal_light_mix
            );
        }
        if !(self.beta.is_finite() && self.beta > 0.0) {
            bail!("--beta must be positive, got {}", self.beta);
        }
        let mis = match self.mis {
            Mis::Balance => MisHeuristic::Balance,
            Mis::Power => MisHeuristic::Power { beta: self.beta },
        };
        let desc = scene_arg::load(&self.scene, self.scene_options)?;
        let (width, height) = resolution.unwrap_or((desc.defaults.width, desc.defaults.height));
        let options = IntegratorOptions {
            max_depth: self.max_depth.unwrap_or(desc.defaults.max_depth),
            mis,
            rr_depth: self.rr_depth,
        };
        let integrator = match self.portals.as_deref() {
            Some("auto") if self.integrator == "lp_hf" => None,
            Some("auto") => bail!("--portals auto is for --integrator lp_hf"),
            portals => {
                let portals = match portals {
                    Some(file) => {
                        Portals::read_json(Path::new(file)).map_err(anyhow::Error::msg)?
                    }
                    None => Portals::from_quads(&desc.portals),
                };
                Some(
                    integrator::by_name(
                        &self.integrator,
                        options.clone(),
                        portals,
                        self.portal_light_mix,
                    )
                    .map_err(anyhow::Error::msg)?,
                )
            }
        };
        let spp = match time {
            Some(_) => self.spp.unwrap_or(u32::MAX),
            None => self.spp.unwrap_or(desc.defaults.spp),
        };
        let settings = RenderSettings {
            spp,
            time_limit: time,
            seed: self.seed,
        };
        Ok(Job {
            desc,
            width,
            height,
            integrator,
            options,
            settings,
        })
    }

    /// Runs the job on a pool of --threads workers, with Ctrl-C stopping it cleanly.
    fn run(
        &self,
        job: Job,
        hook: Option<fenestra_render::integrator::PassHook>,
    ) -> Result<(RenderStats, Film)> {
        let pool = crate::thread_pool(self.threads)?;
        let cancel = Arc::new(AtomicBool::new(false));
        let flag = cancel.clone();
        // First Ctrl-C: finish the rows in flight and write what is done; second: quit at once.
        let _ = ctrlc::set_handler(move || {
            if flag.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
            eprintln!(
                "\ninterrupted: writing the samples taken so far (Ctrl-C again to quit at once)"
            );
        });
        let prepared = &job.integrator;
        let desc = job.desc;
        pool.install(|| -> Result<_> {
            let scene =
                Scene::build(desc, self.bvh.unwrap_or_default()).context("invalid scene")?;
            let render_scene = RenderScene::new(scene, self.light_selection);
            let estimated;
            let integrator = match prepared {
                Some(i) => i.as_ref(),
                None => {
                    let quiet = self.quiet || self.json;
                    let portals =
                        crate::portals_cmd::auto(&render_scene, self.portal_model, quiet, &cancel)?
                            .with_strategy(self.portal_sampling, self.portal_choice);
                    estimated = integrator::by_name(
                        "lp_hf",
                        job.options.clone(),
                        portals,
                        self.portal_light_mix,
                    )
                    .map_err(anyhow::Error::msg)?;
                    estimated.as_ref()
                }
            };
            let mut film = Film::new(job.width, job.height);
            let bar = Bar::new(self.quiet || self.json);
            let mut control = RenderControl::new(&cancel, &bar);
            control.on_pass = hook;
            let stats = integrator.render(&render_scene, &mut film, &job.settings, &control);
            bar.finish();
            Ok((stats, film))
        })
    }

    fn report(
        &self,
        output: &Path,
        stats: &RenderStats,
        sidecar: &serde_json::Value,
    ) -> Result<()> {
        if self.json {
            println!("{}", serde_json::to_string(sidecar)?);
        } else {
            println!("{}", stats.summary());
            let (png, json) = output::companion_paths(output);
            println!(
                "wrote {}, {}, {}",
                output.display(),
                png.display(),
                json.display()
            );
        }
        Ok(())
    }
}

fn check_exr(path: &Path) -> Result<()> {
    if path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
        != Some("exr")
    {
        bail!(
            "output {} must end in .exr (the PNG and JSON are written beside it)",
            path.display()
        );
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create output folder {}", dir.display()))?;
    }
    Ok(())
}

/// Renders; returns whether the render was interrupted (its partial result is written).
pub fn run(args: RenderArgs) -> Result<bool> {
    check_exr(&args.output)?;
    if let Some(t) = args.target_rel_mse {
        if !(t.is_finite() && t > 0.0) {
            bail!("--target-rel-mse must be positive, got {t}");
        }
    }
    let job = args.opts.job(args.time)?;
    let reference = match &args.reference {
        Some(p) => {
            let r = Image::read(p)?;
            if (r.width, r.height) != (job.width as usize, job.height as usize) {
                bail!(
                    "reference {} is {}x{}, the render {}x{}",
                    p.display(),
                    r.width,
                    r.height,
                    job.width,
                    job.height
                );
            }
            Some(r)
        }
        None => None,
    };
    // Convergence: metrics against the reference after every pass.
    let curve = Mutex::new(Vec::new());
    let hook = |film: &Film, time_s: f64| -> bool {
        let Some(r) = &reference else { return true };
        let Ok(m) = metrics::compare(&film.image(), r) else {
            return true;
        };
        let spp = film.sample_count_range().0;
        if let Ok(mut c) = curve.lock() {
            c.push(json!({ "spp": spp, "time_s": time_s, "mse": m.mse, "rel_mse": m.rel_mse }));
        }
        args.target_rel_mse.is_none_or(|t| m.rel_mse > t)
    };
    let (stats, film) = args.opts.run(job, Some(&hook))?;
    let mut sidecar = serde_json::to_value(&stats)?;
    if reference.is_some() {
        sidecar["convergence"] = json!(curve.into_inner().unwrap_or_default());
    }
    output::write_render(
        &args.output,
        &film,
        &stats,
        &sidecar,
        args.opts.exposure,
        args.variance,
    )?;
    args.opts.report(&args.output, &stats, &sidecar)?;
    Ok(stats.interrupted)
}

/// Renders a reference into the cache, or finds it there; prints where it is.
pub fn reference(args: ReferenceArgs) -> Result<()> {
    let job = args.opts.job(None)?;
    // Everything that changes the picture goes into the key.
    let key = debug_hash(&(
        &job.desc,
        &args.opts.integrator,
        format!("{:?}", job.options),
        job.width,
        job.height,
        job.settings.spp,
        job.settings.seed,
        format!("{:?}", args.opts.light_selection),
        env!("CARGO_PKG_VERSION"),
    ));
    let path = args.cache.join(format!(
        "{}-{key:016x}.exr",
        fenestra_eval::suite::slug(&job.desc.name)
    ));
    let sidecar_path = output::companion_paths(&path).1;
    if path.exists() && sidecar_path.exists() && output::variance_path(&path).exists() {
        let summary = json!({ "path": path, "cached": true, "sidecar": sidecar_path });
        if args.opts.json {
            println!("{summary}");
        } else {
            println!("reference {} (cached)", path.display());
        }
        return Ok(());
    }
    check_exr(&path)?;
    let (stats, film) = args.opts.run(job, None)?;
    if stats.interrupted {
        bail!("reference interrupted: nothing cached");
    }
    let mut sidecar = serde_json::to_value(&stats)?;
    sidecar["reference_key"] = json!(format!("{key:016x}"));
    output::write_render(&path, &film, &stats, &sidecar, args.opts.exposure, true)?;
    if args.opts.json {
        println!(
            "{}",
            json!({ "path": path, "cached": false, "sidecar": sidecar_path, "time_s": stats.time_s })
        );
    } else {
        println!(
            "{}\nreference {} (rendered)",
            stats.summary(),
            path.display()
        );
    }
    Ok(())
}
