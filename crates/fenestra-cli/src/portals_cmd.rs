//! `fenestra portals`: estimate light portals (seed 000 ch. 4) and write portals.json, a
//! picture of the photons and portals, and optional pbrt/OBJ exports.

use crate::{progress::Bar, scene_arg};
use anyhow::{bail, Context, Result};
use clap::Args;
use fenestra_portals::estimate::{estimate, Estimate, EstimateParams, Model};
use fenestra_portals::photon::Deposit;
use fenestra_portals::{export, plot};
use fenestra_render::portal::{Portal, PortalFile, Portals};
use fenestra_render::{LightSelection, RenderScene};
use fenestra_scene::{Backend, Scene};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The pipeline's parameters, named as in seed 000 §5.2: PT(theta, n, r), DBSCAN(eps, m),
/// RANSAC(eps, tau, N), MVCE(eps).
#[derive(Args, Clone, Debug)]
pub struct EstimateOpts {
    /// PT: cone half-angle theta of a beam, degrees.
    #[arg(long, default_value_t = 3.0)]
    theta: f32,
    /// PT: rays per beam n.
    #[arg(long, default_value_t = 32)]
    rays: u32,
    /// PT: radius r of the rejection sphere, metres (depth discontinuities shorter than r
    /// deposit nothing).
    #[arg(long, default_value_t = 1.2)]
    radius: f32,
    /// Where photons are deposited: depth (discontinuities, Alg. 1) or material (on glass,
    /// §5.3). Default: material when the scene has glass, depth otherwise.
    #[arg(long)]
    deposit: Option<Deposit>,
    /// Photons to gather (default: 8192 by depth, 32768 by material).
    #[arg(long)]
    photons: Option<usize>,
    /// Give up after this many beams if the photons are not gathered.
    #[arg(long, default_value_t = 1 << 22)]
    max_beams: u64,
    /// DBSCAN: neighbourhood radius eps, metres.
    #[arg(long, default_value_t = 0.125)]
    eps: f32,
    /// DBSCAN: minimum neighbours m of a core point.
    #[arg(long, default_value_t = 16)]
    min_points: usize,
    /// RANSAC: inlier distance to the plane, metres.
    #[arg(long, default_value_t = 0.07)]
    ransac_eps: f64,
    /// RANSAC: inlier fraction that ends the search.
    #[arg(long, default_value_t = 0.07)]
    ransac_tau: f64,
    /// RANSAC: maximum trials N.
    #[arg(long, default_value_t = 1024)]
    ransac_trials: usize,
    /// MVCE: Khachiyan's stopping tolerance.
    #[arg(long, default_value_t = 1e-3)]
    mvce_eps: f64,
    /// Portal shape: ellipse (MVCE, the seed's), pca (PCA rectangle), rectangle (minimum
    /// area) or smallest (the smaller of ellipse and rectangle).
    #[arg(long, default_value = "smallest")]
    model: Model,
    #[arg(long, default_value_t = 0)]
    seed: u64,
}

impl Default for EstimateOpts {
    fn default() -> Self {
        use clap::Parser;
        #[derive(Parser)]
        struct Defaults {
            #[command(flatten)]
            opts: EstimateOpts,
        }
        Defaults::parse_from(["defaults"]).opts
    }
}

impl EstimateOpts {
    pub fn params(&self) -> EstimateParams {
        let mut p = EstimateParams::default();
        p.photons.theta_deg = self.theta;
        p.photons.rays_per_beam = self.rays;
        p.photons.reject_radius = self.radius;
        p.photons.deposit = self.deposit;
        p.photons.target = self.photons;
        p.photons.max_beams = self.max_beams;
        p.photons.seed = self.seed;
        p.dbscan.eps = self.eps;
        p.dbscan.min_points = self.min_points;
        p.ransac.eps = self.ransac_eps;
        p.ransac.tau = self.ransac_tau;
        p.ransac.trials = self.ransac_trials;
        p.ransac.seed = self.seed;
        p.mvce_eps = self.mvce_eps;
        p.model = self.model;
        p
    }
}

#[derive(Args)]
pub struct PortalsArgs {
    /// builtin:NAME, a pbrt-v4 scene file, or an OBJ/PLY mesh.
    scene: String,
    #[command(flatten)]
    scene_options: scene_arg::SceneOptions,
    /// Output portals.json.
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    estimate: EstimateOpts,
    /// Also write the portals as pbrt-v4 shapes (FILE.pbrt) or OBJ polygons (FILE.obj);
    /// may be given several times.
    #[arg(long)]
    export: Vec<PathBuf>,
    /// Picture of photons, clusters and portals on XY, XZ and YZ (default: beside the
    /// output, with .png).
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Ray-query backend: embree or obvhs.
    #[arg(long)]
    bvh: Option<Backend>,
    /// Print the result as JSON.
    #[arg(long)]
    json: bool,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

/// Estimates portals on a built scene with a progress bar; `cancel` ends photon tracing
/// early (the photons gathered so far are used).
pub fn estimate_on(
    scene: &RenderScene,
    opts: &EstimateOpts,
    quiet: bool,
    cancel: &AtomicBool,
) -> Result<Estimate> {
    let bar = Bar::new(quiet);
    let e = estimate(scene, &opts.params(), cancel, &bar).map_err(anyhow::Error::msg)?;
    bar.finish();
    Ok(e)
}

pub fn build_scene(
    arg: &str,
    options: scene_arg::SceneOptions,
    bvh: Option<Backend>,
) -> Result<RenderScene> {
    let desc = scene_arg::load(arg, options)?;
    let scene = Scene::build(desc, bvh.unwrap_or_default()).context("invalid scene")?;
    Ok(RenderScene::new(scene, LightSelection::Power))
}

fn kind(p: &Portal) -> &'static str {
    match p {
        Portal::Quad { .. } => "quad",
        Portal::Triangle { .. } => "triangle",
        Portal::Ellipse { .. } => "ellipse",
    }
}

/// Size in words: semi-axes of an ellipse, edge lengths of a quad.
fn size(p: &Portal) -> String {
    match p {
        Portal::Quad { e1, e2, .. } => format!("{:.4} x {:.4} m", e1.length(), e2.length()),
        Portal::Ellipse { a, b, .. } => {
            format!("semi-axes {:.4}, {:.4} m", a.length(), b.length())
        }
        Portal::Triangle { .. } => "triangle".into(),
    }
}

fn v3(v: fenestra_core::Vec3) -> String {
    format!("({:.3}, {:.3}, {:.3})", v.x, v.y, v.z)
}

/// A one-paragraph account of an estimate (stderr for `render --portals auto`).
pub fn summary(e: &Estimate) -> String {
    let ph = &e.photons;
    let noise = ph.points.len() - e.clusters.iter().map(Vec::len).sum::<usize>();
    let mut s = format!(
        "{} photons ({:?} deposits) from {} beams, {} rays{}; {} clusters, {} noise photons; {} portals in {:.2} s (photons {:.2} s, DBSCAN {:.2} s, fitting {:.2} s)",
        ph.points.len(),
        ph.deposit,
        ph.beams,
        ph.rays,
        if ph.interrupted {
            ", interrupted".to_string()
        } else if ph.points.len() < ph.target {
            format!(" (the beam limit came before the {} aimed at)", ph.target)
        } else {
            String::new()
        },
        e.clusters.len(),
        noise,
        e.portals.len(),
        e.timings.total(),
        e.timings.photons,
        e.timings.clustering,
        e.timings.fitting,
    );
    for (k, p) in e.portals.iter().enumerate() {
        s.push_str(&format!(
            "\n  portal {k}: {} centre {} normal {} {}, area {:.5} m^2, {} photons ({} inliers)",
            kind(&p.portal),
            v3(p.portal.center()),
            v3(p.portal.normal()),
            size(&p.portal),
            p.portal.area(),
            p.photons,
            p.inliers
        ));
    }
    s
}

pub fn run(args: PortalsArgs) -> Result<()> {
    if args.output.extension().and_then(|e| e.to_str()) != Some("json") {
        bail!("output {} must end in .json", args.output.display());
    }
    for path in &args.export {
        match path.extension().and_then(|e| e.to_str()) {
            Some("pbrt" | "obj") => {}
            _ => bail!("--export {}: expected a .pbrt or .obj file", path.display()),
        }
    }
    if let Some(dir) = args.output.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create output folder {}", dir.display()))?;
    }
    let pool = crate::thread_pool(args.threads)?;
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    // First Ctrl-C: stop tracing photons and fit what is gathered; second: quit at once.
    let _ = ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
        eprintln!("\ninterrupted: fitting portals to the photons gathered so far");
    });
    let (e, bounds) = pool.install(|| -> Result<_> {
        let scene = build_scene(&args.scene, args.scene_options, args.bvh)?;
        let e = estimate_on(&scene, &args.estimate, args.quiet || args.json, &cancel)?;
        Ok((e, scene.scene.bounds()))
    })?;
    let params = args.estimate.params();
    if e.portals.is_empty() {
        eprintln!(
            "warning: no portal found ({} photons, {} clusters); try more --photons, a larger --theta or a smaller --radius",
            e.photons.points.len(),
            e.clusters.len()
        );
    }
    let file = PortalFile {
        portals: e.portals.iter().map(|p| p.record()).collect(),
    };
    let mut doc = serde_json::to_value(&file)?;
    doc["estimation"] = json!({
        "scene": args.scene,
        "parameters": params,
        "photons": e.photons.points.len(),
        "beams": e.photons.beams,
        "rays": e.photons.rays,
        "deposit": e.photons.deposit,
        "interrupted": e.photons.interrupted,
        "clusters": e.clusters.len(),
        "time_s": e.timings,
    });
    write_atomically(&args.output, &serde_json::to_string_pretty(&doc)?)?;
    let portals: Vec<Portal> = e.portals.iter().map(|p| p.portal.clone()).collect();
    for path in &args.export {
        export::write(&portals, path).map_err(anyhow::Error::msg)?;
    }
    let plot_path = args
        .plot
        .clone()
        .unwrap_or_else(|| args.output.with_extension("png"));
    plot::write_projections(&e, bounds, &plot_path).map_err(anyhow::Error::msg)?;
    if args.json {
        println!("{doc}");
    } else {
        println!("{}", summary(&e));
        let mut wrote = vec![
            args.output.display().to_string(),
            plot_path.display().to_string(),
        ];
        wrote.extend(args.export.iter().map(|p| p.display().to_string()));
        println!("wrote {}", wrote.join(", "));
    }
    Ok(())
}

/// Portals for `render --portals auto`: estimated with the default parameters and the
/// shape `model`, reported on stderr.
pub fn auto(
    scene: &RenderScene,
    model: Model,
    quiet: bool,
    cancel: &AtomicBool,
) -> Result<Portals> {
    let opts = EstimateOpts {
        model,
        ..EstimateOpts::default()
    };
    let e = estimate_on(scene, &opts, quiet, cancel)?;
    if !quiet {
        eprintln!("portals: {}", summary(&e));
    }
    if e.portals.is_empty() {
        bail!("--portals auto found no portal in this scene; see `fenestra portals` to tune the estimation");
    }
    Ok(e.portals())
}

fn write_atomically(path: &Path, text: &str) -> Result<()> {
    let tmp = path.with_extension("json.partial");
    std::fs::write(&tmp, text)
        .and_then(|_| std::fs::rename(&tmp, path))
        .with_context(|| format!("cannot write {}", path.display()))
}
