//! `fenestra render` and `fenestra reference`.

use crate::files::Files;
use crate::integrators::{self, Config, IntegratorArgs};
use crate::{interrupt, progress::Bar, scene_arg};
use anyhow::{bail, Context, Result};
use clap::Args;
use fenestra_core::image::Image;
use fenestra_core::stats::ConvergencePoint;
use fenestra_eval::hash::debug_hash;
use fenestra_eval::metrics;
use fenestra_eval::run::{ReferenceSummary, REFERENCE_SEED_OFFSET};
use fenestra_render::control::PassHook;
use fenestra_render::integrator::WorkMap;
use fenestra_render::{
    output, Film, Integrator, RenderControl, RenderScene, RenderSettings, RenderStats,
};
use fenestra_scene::{Backend, Scene};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// What is rendered and how: shared by `render` and `reference`.
#[derive(Args)]
pub struct RenderOpts {
    /// builtin:NAME (see `fenestra list`), a pbrt-v4 scene file, or an OBJ/PLY mesh.
    scene: String,
    #[command(flatten)]
    scene_options: scene_arg::SceneOptions,
    /// Samples per pixel (default: the scene's).
    #[arg(long)]
    spp: Option<u32>,
    /// Random seed: a pixel's samples depend only on it, the pixel and the sample index.
    /// `reference` renders in a seed space of its own (seed + 2^40), so that a reference
    /// never shares random numbers with a render.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Image size as WxH (default: the scene's).
    #[arg(long)]
    resolution: Option<String>,
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
    // Last: its option groups come under their own headings in --help.
    #[command(flatten)]
    integrator: IntegratorArgs,
}

#[derive(Args)]
pub struct RenderArgs {
    /// Render for this many seconds instead of a fixed sample count (with --spp: whichever
    /// comes first). Preparation (such as --portals auto) comes on top; the sidecar's time_s
    /// includes it and prepare_s says how much it was.
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
    /// Also write pictures of the integrator's own work, if it makes any (ias: passes,
    /// shadow rays, visible share, clusters per cut, anti-aliasing regions per pixel) into
    /// the folder OUT-maps, as false-colour PNGs with their scales in scales.json.
    #[arg(long)]
    maps: bool,
    /// Output EXR; the PNG and JSON sidecar are written beside it.
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    opts: RenderOpts,
}

#[derive(Args)]
pub struct ReferenceArgs {
    /// Folder of cached references, keyed by scene content, settings and resolution.
    #[arg(long, default_value = "refs")]
    cache: PathBuf,
    #[command(flatten)]
    opts: RenderOpts,
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
    /// What the render reads: scene files, a portals file.
    inputs: Files,
    width: u32,
    height: u32,
    integrator: Box<dyn Integrator>,
    settings: RenderSettings,
}

impl Job {
    /// Everything that changes the picture: the reference cache key.
    fn key(&self, backend: Backend) -> u64 {
        debug_hash(&(
            &self.desc,
            self.integrator.name(),
            self.integrator.settings().to_string(),
            self.width,
            self.height,
            self.settings.spp,
            self.settings.seed,
            backend.name(),
            env!("CARGO_PKG_VERSION"),
        ))
    }
}

impl RenderOpts {
    /// Checks every argument and builds the integrator before the (possibly long) scene
    /// build.
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
        if let Some(e) = self.exposure.filter(|e| !e.is_finite()) {
            bail!("--exposure must be a finite number of stops, got {e}");
        }
        if self.spp == Some(0) {
            bail!("--spp must be at least 1");
        }
        self.integrator.check()?;
        let loaded = scene_arg::load(&self.scene, self.scene_options)?;
        let desc = loaded.desc;
        let mut inputs = Files::default();
        inputs.inputs(&loaded.files, "scene file");
        if let Some(p) = self
            .integrator
            .portals
            .portals
            .as_deref()
            .filter(|&p| p != "auto")
        {
            inputs.input(Path::new(p), "portals file");
        }
        let (width, height) = resolution.unwrap_or((desc.defaults.width, desc.defaults.height));
        let config = Config {
            path: self.integrator.path.options(desc.defaults.max_depth)?,
            args: &self.integrator,
        };
        let integrator = integrators::registry().build(&self.integrator.integrator, &config)?;
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
            inputs,
            width,
            height,
            integrator,
            settings,
        })
    }

    /// Builds the scene, prepares the integrator and renders, on a pool of --threads workers,
    /// with Ctrl-C stopping it cleanly.
    fn run(&self, job: Job, hook: Option<PassHook>) -> Result<(RenderStats, Film, Vec<WorkMap>)> {
        let pool = crate::thread_pool(self.threads)?;
        let cancel = interrupt::on_ctrl_c("writing the samples taken so far");
        let Job {
            desc,
            inputs: _,
            width,
            height,
            mut integrator,
            settings,
        } = job;
        pool.install(|| -> Result<_> {
            let scene =
                Scene::build(desc, self.bvh.unwrap_or_default()).context("invalid scene")?;
            let scene = RenderScene::new(scene);
            let mut film = Film::new(width, height);
            let bar = Bar::new(self.quiet || self.json);
            let mut control = RenderControl::new(&cancel, &bar);
            control.on_pass = hook;
            let stats = fenestra_render::render(
                integrator.as_mut(),
                &scene,
                &mut film,
                &settings,
                &control,
            );
            bar.finish();
            Ok((stats?, film, integrator.work_maps()))
        })
    }

    fn report(&self, output: &Path, stats: &RenderStats) -> Result<()> {
        if self.json {
            println!("{}", serde_json::to_string(stats)?);
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

/// Checks a cached reference before serving it: its sidecar names `key` and a finished
/// render, and its image and variance image read back at the render's size.
fn verify_reference(path: &Path, key: &str, width: u32, height: u32) -> Result<()> {
    let sidecar = output::companion_paths(path).1;
    let text = std::fs::read_to_string(&sidecar)
        .with_context(|| format!("cannot read {}", sidecar.display()))?;
    let stats: RenderStats = serde_json::from_str(&text)
        .with_context(|| format!("{} is not a render's sidecar", sidecar.display()))?;
    if stats.reference_key.as_deref() != Some(key) || stats.interrupted {
        bail!("its sidecar is not that of this reference");
    }
    for image in [path.to_path_buf(), output::variance_path(path)] {
        let img = Image::read(&image)?;
        if (img.width, img.height) != (width as usize, height as usize) {
            bail!("{} is {}x{}", image.display(), img.width, img.height);
        }
    }
    Ok(())
}

/// Adds the files a render writes for OUT.exr: OUT.png, OUT.json and, with `variance`,
/// OUT.var.exr.
fn render_outputs<'a>(files: &'a mut Files, exr: &Path, variance: bool) -> &'a mut Files {
    let (png, json) = output::companion_paths(exr);
    files
        .output(exr, "image")
        .output(&png, "picture")
        .output(&json, "sidecar");
    if variance {
        files.output(&output::variance_path(exr), "variance image");
    }
    files
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
    let mut job = args.opts.job(args.time)?;
    let mut files = std::mem::take(&mut job.inputs);
    if let Some(r) = &args.reference {
        files.input(r, "reference");
    }
    let maps_dir = maps_folder(&args.output);
    if args.maps {
        files.folder(&maps_dir, "work maps folder");
    }
    render_outputs(&mut files, &args.output, args.variance).check()?;
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
        if let Ok(mut c) = curve.lock() {
            c.push(ConvergencePoint {
                spp: film.sample_count_range().0,
                time_s,
                mse: m.mse,
                rel_mse: m.rel_mse,
            });
        }
        args.target_rel_mse.is_none_or(|t| m.rel_mse > t)
    };
    let (mut stats, film, maps) = args.opts.run(job, Some(&hook))?;
    if stats.interrupted && stats.spp_max == 0 {
        // Stopped before the first sample (while the scene was being built): a black image
        // would only replace whatever was there.
        eprintln!("interrupted before any sample: nothing written");
        return Ok(true);
    }
    stats.convergence = curve.into_inner().unwrap_or_default();
    output::write_render(
        &args.output,
        &film,
        &stats,
        args.opts.exposure,
        args.variance,
    )?;
    args.opts.report(&args.output, &stats)?;
    if args.maps {
        write_maps(&maps_dir, &maps, film.width, film.height, &stats.integrator)?;
    }
    Ok(stats.interrupted)
}

/// Where `--maps` writes for OUT.exr: the folder OUT-maps beside it.
fn maps_folder(exr: &Path) -> PathBuf {
    let stem = exr
        .file_stem()
        .map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
    exr.with_file_name(format!("{stem}-maps"))
}

/// Writes each work map as a false-colour PNG NAME.png (inferno, from 0 to the map's
/// largest value) and, in scales.json, what each shows and its largest value; each file
/// atomically, under the same names every time.
fn write_maps(
    dir: &Path,
    maps: &[WorkMap],
    width: u32,
    height: u32,
    integrator: &str,
) -> Result<()> {
    if maps.is_empty() {
        eprintln!("note: {integrator} makes no work maps; --maps wrote nothing");
        return Ok(());
    }
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let mut scales = serde_json::Map::new();
    for m in maps {
        let top = m.values.iter().copied().fold(0.0f32, f32::max);
        let mut img = image::RgbImage::new(width, height);
        for (i, v) in m.values.iter().enumerate() {
            let t = if top > 0.0 { v / top } else { 0.0 };
            let (x, y) = (i as u32 % width, i as u32 / width);
            img.put_pixel(x, y, image::Rgb(fenestra_eval::colormap::inferno(t)));
        }
        let path = dir.join(format!("{}.png", m.name));
        fenestra_core::fs::write_atomically(&path, |tmp| {
            img.save_with_format(tmp, image::ImageFormat::Png)
        })?;
        println!(
            "wrote {} ({}; black 0, yellow {})",
            path.display(),
            m.what,
            scale_label(top)
        );
        scales.insert(
            m.name.into(),
            serde_json::json!({ "what": m.what, "max": top }),
        );
    }
    let json = serde_json::to_string_pretty(&scales)?;
    fenestra_core::fs::write_text_atomically(&dir.join("scales.json"), &json)?;
    Ok(())
}

/// A map's largest value as a file name piece: 3 significant digits.
fn scale_label(v: f32) -> String {
    if v >= 100.0 || v == v.round() {
        format!("{v:.0}")
    } else {
        format!("{v:.3}")
    }
}

/// Renders a reference into the cache, or finds it there; prints where it is.
pub fn reference(args: ReferenceArgs) -> Result<()> {
    let mut job = args.opts.job(None)?;
    job.settings.seed = job.settings.seed.wrapping_add(REFERENCE_SEED_OFFSET);
    let key = job.key(args.opts.bvh.unwrap_or_default());
    let path = args.cache.join(format!(
        "{}-{key:016x}.exr",
        fenestra_eval::suite::slug(&job.desc.name)
    ));
    let sidecar = output::companion_paths(&path).1;
    let mut summary = ReferenceSummary {
        path: path.clone(),
        cached: true,
        sidecar: sidecar.clone(),
        key: format!("{key:016x}"),
    };
    let cached = match verify_reference(&path, &format!("{key:016x}"), job.width, job.height) {
        Ok(()) => true,
        Err(why) => {
            if path.exists() && !args.opts.quiet {
                eprintln!(
                    "cached reference {} is unusable ({why}): rendering it again",
                    path.display()
                );
            }
            false
        }
    };
    if !cached {
        check_exr(&path)?;
        let mut files = std::mem::take(&mut job.inputs);
        render_outputs(&mut files, &path, true).check()?;
        let (mut stats, film, _) = args.opts.run(job, None)?;
        if stats.interrupted {
            bail!("reference interrupted: nothing cached");
        }
        stats.reference_key = Some(format!("{key:016x}"));
        output::write_render(&path, &film, &stats, args.opts.exposure, true)?;
        if !args.opts.json {
            println!("{}", stats.summary());
        }
        summary.cached = false;
    }
    if args.opts.json {
        println!("{}", serde_json::to_string(&summary)?);
    } else {
        let how = if summary.cached { "cached" } else { "rendered" };
        println!("reference {} ({how})", path.display());
    }
    Ok(())
}
