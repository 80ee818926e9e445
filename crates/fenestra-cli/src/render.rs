//! `fenestra render`.

use crate::{progress::Bar, scene_arg};
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use fenestra_core::mis::MisHeuristic;
use fenestra_render::integrator::{self, IntegratorOptions};
use fenestra_render::{output, Film, LightSelection, RenderControl, RenderScene, RenderSettings};
use fenestra_scene::{Backend, Scene};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

#[derive(Clone, Copy, ValueEnum)]
enum Mis {
    Balance,
    Power,
}

#[derive(Args)]
pub struct RenderArgs {
    /// builtin:NAME (see `fenestra list`) or a scene file.
    scene: String,
    /// Integrator: hf (BSDF sampling) or af_hf (light and BSDF sampling with MIS).
    #[arg(long, default_value = "af_hf")]
    integrator: String,
    /// Samples per pixel (default: the scene's).
    #[arg(long, conflicts_with = "time")]
    spp: Option<u32>,
    /// Render for this many seconds instead of a fixed sample count.
    #[arg(long, allow_negative_numbers = true)]
    time: Option<f64>,
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
    /// Output EXR; the PNG and JSON sidecar are written beside it.
    #[arg(short, long)]
    output: PathBuf,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
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
    Ok((w, h))
}

/// Renders; returns whether the render was interrupted (its partial result is written).
pub fn run(args: RenderArgs) -> Result<bool> {
    // Check every argument before the (possibly long) scene build.
    let resolution = args
        .resolution
        .as_deref()
        .map(parse_resolution)
        .transpose()?;
    if args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
        != Some("exr")
    {
        bail!(
            "output {} must end in .exr (the PNG and JSON are written beside it)",
            args.output.display()
        );
    }
    if let Some(t) = args.time {
        if !(t.is_finite() && t > 0.0) {
            bail!("--time must be a positive number of seconds, got {t}");
        }
    }
    if args.spp == Some(0) {
        bail!("--spp must be at least 1");
    }
    if args.max_depth == Some(0) {
        bail!("--max-depth must be at least 1 (1 = emitters seen directly, 2 = direct light)");
    }
    if !(args.beta.is_finite() && args.beta > 0.0) {
        bail!("--beta must be positive, got {}", args.beta);
    }
    let mis = match args.mis {
        Mis::Balance => MisHeuristic::Balance,
        Mis::Power => MisHeuristic::Power { beta: args.beta },
    };
    let desc = scene_arg::load(&args.scene)?;
    let (width, height) = resolution.unwrap_or((desc.defaults.width, desc.defaults.height));
    let options = IntegratorOptions {
        max_depth: args.max_depth.unwrap_or(desc.defaults.max_depth),
        mis,
        rr_depth: args.rr_depth,
    };
    let integrator = integrator::by_name(&args.integrator, options).map_err(anyhow::Error::msg)?;
    let settings = RenderSettings {
        spp: if args.time.is_some() {
            args.spp.unwrap_or(u32::MAX)
        } else {
            args.spp.unwrap_or(desc.defaults.spp)
        },
        time_limit: args.time,
        seed: args.seed,
    };
    if let Some(dir) = args.output.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create output folder {}", dir.display()))?;
    }

    let pool = crate::thread_pool(args.threads)?;

    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    // First Ctrl-C: finish the rows in flight and write what is done; second: quit at once.
    let _ = ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
        eprintln!("\ninterrupted: writing the samples taken so far (Ctrl-C again to quit at once)");
    });

    let (stats, film) = pool.install(|| -> Result<_> {
        let scene = Scene::build(desc, args.bvh.unwrap_or_default()).context("invalid scene")?;
        let render_scene = RenderScene::new(scene, args.light_selection);
        let mut film = Film::new(width, height);
        let bar = Bar::new(args.quiet || args.json);
        let control = RenderControl {
            cancel: &cancel,
            progress: &bar,
        };
        let stats = integrator.render(&render_scene, &mut film, &settings, &control);
        bar.finish();
        Ok((stats, film))
    })?;
    output::write_render(&args.output, &film, &stats, args.exposure)?;
    if args.json {
        println!("{}", serde_json::to_string(&stats)?);
    } else {
        println!("{}", stats.summary());
        let (png, json) = output::companion_paths(&args.output);
        println!(
            "wrote {}, {}, {}",
            args.output.display(),
            png.display(),
            json.display()
        );
    }
    Ok(stats.interrupted)
}
