//! `fenestra portals`: estimate light portals (seed 000 ch. 4) and write portals.json, a
//! picture of the photons and portals, and optional pbrt/OBJ exports.

use crate::support::{interrupt, progress::Bar, scene_arg};
use anyhow::{bail, Context, Result};
use clap::Args;
use fenestra_core::fs::FileSet;
use fenestra_portals::estimate::{estimate, EstimateParams, Model};
use fenestra_portals::photon::Deposit;
use fenestra_portals::{export, plot, Portal};
use fenestra_render::RenderScene;
use fenestra_scene::{Backend, Scene};
use std::path::PathBuf;

/// The pipeline's defaults, which the flags show and start from (written once, in the
/// pipeline).
fn defaults() -> EstimateParams {
    EstimateParams::default()
}

/// The pipeline's parameters, named as in seed 000 §5.2: PT(theta, n, r), DBSCAN(eps, m),
/// RANSAC(eps, tau, N), MVCE(eps).
#[derive(Args, Clone, Debug)]
pub struct EstimateOpts {
    /// PT: cone half-angle theta of a beam, degrees.
    #[arg(long, default_value_t = defaults().photons.theta_deg)]
    theta: f32,
    /// PT: rays per beam n.
    #[arg(long, default_value_t = defaults().photons.rays_per_beam)]
    rays: u32,
    /// PT: radius r of the rejection sphere, metres (depth discontinuities shorter than r
    /// deposit nothing).
    #[arg(long, default_value_t = defaults().photons.reject_radius)]
    radius: f32,
    /// Where photons are deposited: depth (discontinuities, Alg. 1) or material (on glass,
    /// §5.3). Default: material when the scene has glass, depth otherwise.
    #[arg(long)]
    deposit: Option<Deposit>,
    /// Photons to gather (default: 8192 by depth, 32768 by material).
    #[arg(long)]
    photons: Option<usize>,
    /// Give up after this many beams if the photons are not gathered.
    #[arg(long, default_value_t = defaults().photons.max_beams)]
    max_beams: u64,
    /// Stop tracing photons once portals fitted to 1.5 times as many photons lie within this
    /// fraction of their size of the previous fit's (0: trace to the photon target).
    #[arg(long, default_value_t = defaults().settle.unwrap_or(0.0))]
    settle: f64,
    /// DBSCAN: neighbourhood radius eps, metres.
    #[arg(long, default_value_t = defaults().dbscan.eps)]
    eps: f32,
    /// DBSCAN: minimum neighbours m of a core point.
    #[arg(long, default_value_t = defaults().dbscan.min_points)]
    min_points: usize,
    /// RANSAC: inlier distance to the plane, metres.
    #[arg(long, default_value_t = defaults().ransac.eps)]
    ransac_eps: f64,
    /// RANSAC: inlier fraction that ends the search.
    #[arg(long, default_value_t = defaults().ransac.tau)]
    ransac_tau: f64,
    /// RANSAC: maximum trials N.
    #[arg(long, default_value_t = defaults().ransac.trials)]
    ransac_trials: usize,
    /// MVCE: Khachiyan's stopping tolerance.
    #[arg(long, default_value_t = defaults().mvce_eps)]
    mvce_eps: f64,
    /// Portal shape: ellipse (MVCE, the seed's), pca (PCA rectangle), rectangle (minimum
    /// area) or smallest (the smaller of ellipse and rectangle).
    #[arg(long, default_value_t = defaults().model)]
    model: Model,
    /// Seed of the photons' and RANSAC's random numbers.
    #[arg(long, default_value_t = defaults().photons.seed)]
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
    /// The parameters as the pipeline takes them.
    pub fn params(&self) -> EstimateParams {
        let mut p = EstimateParams::default();
        p.photons.theta_deg = self.theta;
        p.photons.rays_per_beam = self.rays;
        p.photons.reject_radius = self.radius;
        p.photons.deposit = self.deposit;
        p.photons.target = self.photons;
        p.photons.max_beams = self.max_beams;
        p.settle = (self.settle != 0.0).then_some(self.settle);
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
    /// Picture of photons, clusters and portals on XY, XZ and YZ, with axes in metres, as
    /// SVG (default: beside the output, with .svg); beside it, with .png, the portals over the
    /// scene as its camera sees it.
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

/// Estimates and writes the portals; true if Ctrl-C stopped it (nothing is written then).
pub fn run(args: PortalsArgs) -> Result<bool> {
    if args.output.extension().and_then(|e| e.to_str()) != Some("json") {
        bail!("output {} must end in .json", args.output.display());
    }
    for path in &args.export {
        match path.extension().and_then(|e| e.to_str()) {
            Some("pbrt" | "obj") => {}
            _ => bail!("--export {}: expected a .pbrt or .obj file", path.display()),
        }
    }
    crate::support::files::create_output_folder(&args.output)?;
    let loaded = scene_arg::load(&args.scene, &args.scene_options)?;
    let plot_path = args
        .plot
        .clone()
        .unwrap_or_else(|| args.output.with_extension("svg"));
    let svg = plot_path.extension().and_then(|e| e.to_str()) == Some("svg");
    let view_path = plot_path.with_extension("png");
    let mut files = crate::support::files::Files::default();
    files
        .inputs(&loaded.files, "scene file")
        .output(&args.output, "portals file")
        .output(&plot_path, "picture");
    if svg {
        files.output(&view_path, "camera-view picture");
    }
    for path in &args.export {
        files.output(path, "export");
    }
    files.check()?;
    if !svg {
        bail!(
            "--plot {}: the picture is SVG, name it .svg",
            plot_path.display()
        );
    }
    let pool = crate::thread_pool(args.threads)?;
    let cancel = interrupt::on_ctrl_c("stopping; nothing is written");
    let params = args.estimate.params();
    let (e, scene) = pool.install(|| -> Result<_> {
        let scene =
            Scene::build(loaded.desc, args.bvh.unwrap_or_default()).context("invalid scene")?;
        let scene = RenderScene::new(scene);
        let bar = Bar::new(args.quiet || args.json);
        let e = estimate(&scene, &params, &cancel, &bar)?;
        bar.finish();
        Ok((e, scene))
    })?;
    if cancel.load(std::sync::atomic::Ordering::SeqCst) {
        // Portals of part of the photons would replace a complete estimate: keep the files.
        eprintln!(
            "interrupted: nothing written ({} kept as it was)",
            args.output.display()
        );
        return Ok(true);
    }
    if e.portals.is_empty() {
        eprintln!(
            "warning: no portal found that carries light to what the camera sees ({} photons); lp_hf would sample the lights alone, as af_hf does; more --photons, a larger --theta or a smaller --radius may find one",
            e.photons.points.len(),
        );
    }
    // Every file or none (a full disk wrote the .json and not the .svg).
    let file = e.file(&args.scene, &params);
    let mut set = FileSet::new();
    set.stage(&args.output, |tmp| file.write(tmp))?;
    let portals: Vec<Portal> = e.portals.iter().map(|p| p.portal.clone()).collect();
    for path in &args.export {
        set.stage(path, |tmp| export::write(&portals, tmp))?;
    }
    let bounds = scene.scene.bounds();
    set.stage(&plot_path, |tmp| plot::write_projections(&e, bounds, tmp))?;
    pool.install(|| set.stage(&view_path, |tmp| plot::write_view(&scene.scene, &e, tmp)))?;
    set.commit()?;
    if args.json {
        println!("{}", serde_json::to_string(&file)?);
    } else {
        println!("{}", e.summary());
        let mut wrote = vec![
            args.output.display().to_string(),
            plot_path.display().to_string(),
            view_path.display().to_string(),
        ];
        wrote.extend(args.export.iter().map(|p| p.display().to_string()));
        println!("wrote {}", wrote.join(", "));
    }
    Ok(false)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `render --portals auto` estimates with the pipeline's defaults: they must be this
    /// command's, or the two would find different portals in the same scene.
    #[test]
    fn the_commands_defaults_are_the_pipelines() {
        let json = |p: &EstimateParams| serde_json::to_string(p).expect("json");
        assert_eq!(
            json(&EstimateOpts::default().params()),
            json(&EstimateParams::default())
        );
    }
}
