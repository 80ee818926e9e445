//! `fenestra portals`: estimate light portals (seed 000 ch. 4) and write portals.json, a
//! picture of the photons and portals, and optional pbrt/OBJ exports.

use crate::integrators::{params_given, with_flags};
use crate::support::{interrupt, progress::Bar, scene_arg};
use anyhow::{bail, Context, Result};
use clap::{ArgMatches, Args, Command};
use fenestra_core::fs::FileSet;
use fenestra_portals::estimate::estimate;
use fenestra_portals::EstimateOptions;
use fenestra_portals::{export, plot, Portal};
use fenestra_render::options::Options;
use fenestra_render::registry::Group;
use fenestra_render::RenderScene;
use fenestra_scene::{Backend, Scene};
use fenestra_session::error::option_name_in;
use fenestra_session::Style;
use std::path::PathBuf;

/// The estimator's options, as flags made from its options group (`--theta`, `--rays`, ...).
#[derive(Clone, Debug)]
pub struct EstimateArgs(pub EstimateOptions);

impl EstimateArgs {
    fn group() -> [Group; 1] {
        [EstimateOptions::unprefixed_group()]
    }
}

impl clap::FromArgMatches for EstimateArgs {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let params = params_given(matches, &Self::group());
        EstimateOptions::from_params(&params)
            .map(EstimateArgs)
            .map_err(|e| {
                let flag = option_name_in(&e.key, &Self::group(), Style::Flag);
                let flag = flag.map_or_else(String::new, |f| format!("{f}: "));
                clap::Error::raw(
                    clap::error::ErrorKind::ValueValidation,
                    format!("{flag}{e}\n"),
                )
            })
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl clap::Args for EstimateArgs {
    fn augment_args(cmd: Command) -> Command {
        with_flags(cmd, &Self::group())
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
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
    estimate: EstimateArgs,
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
    fenestra_session::files::create_output_folder(&args.output)?;
    let loaded = scene_arg::load(&args.scene, &args.scene_options)?;
    let plot_path = args
        .plot
        .clone()
        .unwrap_or_else(|| args.output.with_extension("svg"));
    let svg = plot_path.extension().and_then(|e| e.to_str()) == Some("svg");
    let view_path = plot_path.with_extension("png");
    let mut files = fenestra_session::files::Files::default();
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
    let params = args.estimate.0.params();
    let (e, scene) = pool.install(|| -> Result<_> {
        let scene =
            Scene::build(loaded.desc, args.bvh.unwrap_or_default()).context("invalid scene")?;
        let scene = RenderScene::new(scene);
        let bar = Bar::new(args.quiet || args.json);
        let e = estimate(&scene, &params, &cancel, &bar)?;
        bar.finish();
        Ok((e, scene))
    })?;
    // Portals of part of the photons would replace a complete estimate: keep the files. The
    // handler has said nothing is written, so a Ctrl-C while the pictures are drawn counts
    // too: the set is committed only if none came before.
    let interrupted = || {
        let stopped = cancel.load(std::sync::atomic::Ordering::SeqCst);
        if stopped {
            let kept = args.output.display();
            eprintln!("interrupted: nothing written ({kept} kept as it was)");
        }
        stopped
    };
    if interrupted() {
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
    if interrupted() {
        return Ok(true); // the staged files go with the set
    }
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
