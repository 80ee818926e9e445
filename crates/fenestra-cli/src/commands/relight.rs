//! `fenestra relight`: precompute the direct-to-indirect transfer of an animated scene frame by
//! frame (seed 003 ch. 4), then relight the sequence under other lights.

use crate::commands::render::parse_resolution;
use crate::support::interrupt::on_ctrl_c;
use crate::support::scene_arg::{self, SceneOptions};
use anyhow::{anyhow, bail, Context, Result};
use clap::{Args, Subcommand};
use fenestra_lpca::Schedule;
use fenestra_relight::animation::Animation;
use fenestra_relight::frame::{FrameOptions, FrameTransfer};
use fenestra_relight::frame_file;
use fenestra_relight::gather::Gather;
use fenestra_relight::lights_file::LightsFile;
use fenestra_relight::player::{frame_scene, Player};
use fenestra_relight::sequence::AnimatedScene;
use fenestra_relight::store::{Manifest, Store};
use fenestra_scene::filter::{FilterShape, PixelFilter};
use fenestra_session::relight::Opened;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::Instant;

#[derive(Args)]
pub struct RelightArgs {
    #[command(subcommand)]
    command: RelightCommand,
}

#[derive(Subcommand)]
enum RelightCommand {
    /// Precompute an animated scene's transfer, frame by frame, into a folder; interrupted, it
    /// keeps its finished frames and resumes from them when run again.
    Precompute(PrecomputeArgs),
    /// Relight a precomputed sequence under the lights of a lights file: EXR and PNG frames.
    Render(RenderArgs),
    /// Serve a page on 127.0.0.1 that relights a precomputed sequence as you move lights,
    /// change their colour and intensity, scrub and play the frames.
    Serve(ServeArgs),
    /// Write one frame of a precomputed sequence, posed and lit by a lights file, as a pbrt-v4
    /// scene seen through pixel centres: its path-traced ground truth is `fenestra render FILE
    /// --max-depth 3`.
    Export(ExportArgs),
}

#[derive(Args)]
struct ServeArgs {
    /// A folder made by `fenestra relight precompute`.
    dir: PathBuf,
    /// Lights to start from (default: the folder's lights.json).
    #[arg(long)]
    lights: Option<PathBuf>,
    /// Port on 127.0.0.1 (0: any free port).
    #[arg(long, default_value_t = 8017)]
    port: u16,
    /// PNG exposure in stops (default: frame 0's automatic exposure under the first lights).
    #[arg(long, allow_hyphen_values = true)]
    exposure: Option<f32>,
    /// Light samples per light for area lights.
    #[arg(long, default_value_t = 16)]
    light_samples: u32,
    /// Memory for frames kept after their first use, MB.
    #[arg(long, default_value_t = 2048)]
    cache_mb: usize,
    #[arg(long)]
    threads: Option<usize>,
}

#[derive(Args)]
struct ExportArgs {
    /// A folder made by `fenestra relight precompute`.
    dir: PathBuf,
    /// The frame.
    #[arg(long)]
    frame: u32,
    /// Lights file (default: the folder's lights.json).
    #[arg(long)]
    lights: Option<PathBuf>,
    /// Output .pbrt file.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Args)]
struct PrecomputeArgs {
    /// builtin:NAME or a pbrt-v4 file.
    scene: String,
    /// The animation (JSON; docs/relight.md); built-in animated scenes bring their own.
    #[arg(long)]
    animation: Option<PathBuf>,
    /// Output folder.
    #[arg(short, long)]
    output: PathBuf,
    /// Image size WxH (default: the scene's).
    #[arg(long)]
    resolution: Option<String>,
    /// Gather samples on the surfaces.
    #[arg(long, default_value_t = 4096)]
    gather: usize,
    /// Share of view samples whose transfer is evaluated (the rest reconstructed, eq. 4.5).
    #[arg(long, default_value_t = 0.1)]
    explored: f32,
    /// Exploration batches (Alg. 3).
    #[arg(long, default_value_t = 4)]
    batches: usize,
    /// Wavelet coefficients kept per transfer vector.
    #[arg(long, default_value_t = 256)]
    keep: usize,
    /// Wavelet-LPCA clusters per frame.
    #[arg(long, default_value_t = 64)]
    clusters: usize,
    /// Wavelet-LPCA's schedule, DIM:ITERATIONS,...
    #[arg(long, default_value = "0:1,8:2")]
    schedule: String,
    /// The N-body traversal's threshold (area over squared distance).
    #[arg(long, default_value_t = 0.02)]
    threshold: f32,
    /// Evaluate transfer vectors by this many cosine-weighted rays each (Monte Carlo)
    /// instead of the N-body traversal.
    #[arg(long)]
    transfer_rays: Option<u32>,
    /// Explored neighbours whose transfer is combined for a reconstructed view sample (eq. 4.5).
    #[arg(long, default_value_t = 6)]
    neighbours: usize,
    /// Gather samples at which a reconstructed view sample's transfer is evaluated, to fit the
    /// combination's weights (at least --neighbours).
    #[arg(long, default_value_t = 32)]
    elements: usize,
    /// Share of view samples evaluated after reconstruction after all and kept uncompressed:
    /// those whose light under the scene's own lights departs most from their neighbours'.
    #[arg(long, default_value_t = 0.03)]
    refined: f32,
    /// Seed of the gather samples, the exploration's draws and the elements' choice.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Frames to precompute, FIRST..END (END excluded; default all): machines can share a
    /// sequence, each precomputing a range into a copy of the folder.
    #[arg(long)]
    frames: Option<String>,
    /// Worker threads (all cores by default).
    #[arg(long)]
    threads: Option<usize>,
    #[command(flatten)]
    options: SceneOptions,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

#[derive(Args)]
struct RenderArgs {
    /// A folder made by `fenestra relight precompute`.
    dir: PathBuf,
    /// Lights file (default: the folder's lights.json, the scene's own lights).
    #[arg(long)]
    lights: Option<PathBuf>,
    /// Output folder for frame-NNNN.exr and .png.
    #[arg(short, long)]
    output: PathBuf,
    /// Frames to render, FIRST..END (END excluded; default all).
    #[arg(long)]
    frames: Option<String>,
    /// Light samples per light for area lights (Dirac lights take one, exactly).
    #[arg(long, default_value_t = 16)]
    light_samples: u32,
    /// Write the indirect light alone (no direct light, no emitters).
    #[arg(long)]
    indirect_only: bool,
    /// PNG exposure in stops (default: the first frame's automatic exposure, for them all).
    #[arg(long, allow_hyphen_values = true)]
    exposure: Option<f32>,
    #[arg(long)]
    threads: Option<usize>,
    #[arg(long)]
    quiet: bool,
}

pub fn run(args: RelightArgs) -> Result<()> {
    match args.command {
        RelightCommand::Precompute(a) => crate::thread_pool(a.threads)?.install(|| precompute(&a)),
        RelightCommand::Render(a) => crate::thread_pool(a.threads)?.install(|| render(&a)),
        RelightCommand::Export(a) => export(&a),
        RelightCommand::Serve(a) => crate::thread_pool(a.threads)?.install(|| serve(&a)),
    }
}

/// A bar over `total` frames on a terminal.
fn frame_bar(total: u64, quiet: bool) -> ProgressBar {
    let bar = ProgressBar::hidden();
    if !quiet && std::io::stderr().is_terminal() {
        bar.set_draw_target(ProgressDrawTarget::stderr());
    }
    bar.set_length(total);
    bar.set_style(
        ProgressStyle::with_template(
            "[{elapsed_precise}] {wide_bar} frame {pos}/{len} ({eta} left)",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}

/// The scene and its animation: the file given, or the built-in scene's own.
fn animated_scene(
    scene: &str,
    animation: Option<&Path>,
    options: SceneOptions,
) -> Result<(AnimatedScene, String)> {
    let loaded = scene_arg::load(scene, &options)?;
    let (text, name) = match animation {
        Some(p) => (
            std::fs::read_to_string(p).with_context(|| format!("cannot read {}", p.display()))?,
            p.display().to_string(),
        ),
        None => {
            let builtin = scene
                .strip_prefix("builtin:")
                .and_then(fenestra_builtin::animation);
            let text = builtin.ok_or_else(|| {
                anyhow!("{scene} has no animation of its own: give one with --animation A.json (docs/relight.md)")
            })?;
            (text.to_string(), format!("{scene}'s animation"))
        }
    };
    let animation = Animation::parse(&text, &name)?;
    Ok((AnimatedScene::new(loaded.desc, animation)?, text))
}

fn precompute(a: &PrecomputeArgs) -> Result<()> {
    let (animated, text) = animated_scene(&a.scene, a.animation.as_deref(), a.options.clone())?;
    let (width, height) = match &a.resolution {
        Some(r) => {
            let r = parse_resolution(r)?;
            (r.width, r.height)
        }
        None => (animated.rest.defaults.width, animated.rest.defaults.height),
    };
    if !(a.explored > 0.0 && a.explored <= 1.0) {
        bail!("--explored must be in (0, 1], not {}", a.explored);
    }
    if !(0.0..=1.0).contains(&a.refined) {
        bail!("--refined must be in [0, 1], not {}", a.refined);
    }
    if a.gather == 0 || a.keep == 0 || a.clusters == 0 || a.batches == 0 || a.neighbours == 0 {
        // Without neighbours no unexplored pixel could be reconstructed: it would stay dark.
        bail!("--gather, --keep, --clusters, --batches and --neighbours must be at least 1");
    }
    let options = FrameOptions {
        threshold: a.threshold,
        mc_rays: a.transfer_rays.unwrap_or(0),
        explored: a.explored,
        batches: a.batches,
        keep: a.keep,
        clusters: a.clusters,
        schedule: Schedule::parse(&a.schedule)?,
        neighbours: a.neighbours.max(1),
        elements: a.elements.max(a.neighbours),
        ridge: 0.1,
        refined: a.refined,
        seed: a.seed,
    };
    // Scene files are kept by absolute path: `relight render` runs from anywhere.
    let scene = match a.scene.strip_prefix("builtin:") {
        Some(_) => a.scene.clone(),
        None => {
            std::fs::canonicalize(&a.scene).map_or(a.scene.clone(), |p| p.display().to_string())
        }
    };
    let manifest = Manifest::new(&scene, width, height, animated.frames(), a.gather, &options);
    let lights = serde_json::to_string_pretty(&LightsFile::of(&animated.rest.lights))?;
    let store = Store::create_or_resume(&a.output, manifest, &text, &lights)?;
    let range = frame_range(a.frames.as_deref(), animated.frames())?;
    let frames = range.len() as u32;
    let todo: Vec<u32> = range.filter(|&f| !store.done(f)).collect();
    if todo.len() < frames as usize && !a.quiet {
        eprintln!(
            "{} of {frames} frames already precomputed in {}: resuming",
            frames as usize - todo.len(),
            a.output.display()
        );
    }
    let cancel = on_ctrl_c("stopping after the frame being precomputed (finished frames are kept)");
    let rest = frame_scene(&animated, 0, None)?;
    let gather = Gather::new(&rest, a.gather, a.seed);
    let bar = frame_bar(frames as u64, a.quiet);
    bar.set_position(frames as u64 - todo.len() as u64);
    let (mut seconds, mut bytes, mut rays) = (0.0, 0u64, 0u64);
    // Each frame is written while the next is computed: the file (tens of megabytes at
    // 512x512, synced to disk) would otherwise hold both cores idle.
    std::thread::scope(|scope| -> Result<()> {
        let mut writing: Option<std::thread::ScopedJoinHandle<Result<u64>>> = None;
        let mut written = |w: &mut Option<std::thread::ScopedJoinHandle<Result<u64>>>| {
            if let Some(w) = w.take() {
                bytes += w
                    .join()
                    .map_err(|_| anyhow!("writing a frame panicked"))??;
                bar.inc(1);
            }
            Ok::<_, anyhow::Error>(())
        };
        for (k, &f) in todo.iter().enumerate() {
            if cancel.load(Ordering::SeqCst) {
                written(&mut writing)?;
                bar.finish_and_clear();
                eprintln!(
                    "stopped with {} of {frames} frames done: run the same command to resume",
                    frames as usize - todo.len() + k
                );
                std::process::exit(130);
            }
            let start = Instant::now();
            let scene = frame_scene(&animated, f, None)?;
            let posed = gather.posed(&scene);
            let frame = FrameTransfer::precompute(&scene, &posed, width, height, &options);
            let s = start.elapsed().as_secs_f64();
            seconds += s;
            rays += frame.rays;
            written(&mut writing)?;
            let path = store.frame_path(f);
            writing = Some(scope.spawn(move || {
                frame_file::write(&path, &frame, s)?;
                Ok(std::fs::metadata(&path).map_or(0, |m| m.len()))
            }));
        }
        written(&mut writing)
    })?;
    bar.finish_and_clear();
    if !a.quiet && !todo.is_empty() {
        let n = todo.len() as f64;
        // The dense tensor: a 4-byte transfer element per pixel and gather sample per frame.
        let dense = width as f64 * height as f64 * a.gather as f64 * 4.0;
        eprintln!(
            "precomputed {} frames of {width}x{height} over {} gather samples in {seconds:.1} s ({:.2} s a frame, {:.1} M visibility rays a frame); {:.1} MB a frame, {:.0}x smaller than the dense tensor",
            todo.len(),
            a.gather,
            seconds / n,
            rays as f64 / n / 1e6,
            bytes as f64 / n / 1e6,
            dense / (bytes as f64 / n)
        );
    }
    println!("wrote {}", a.output.display());
    Ok(())
}

/// FIRST..END within `frames`.
fn frame_range(s: Option<&str>, frames: u32) -> Result<std::ops::Range<u32>> {
    let Some(s) = s else {
        return Ok(0..frames);
    };
    let bad = || anyhow!("bad --frames '{s}': expected FIRST..END within 0..{frames}, e.g. 0..10");
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    let (a, b): (u32, u32) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if a >= b || b > frames {
        bail!(bad());
    }
    Ok(a..b)
}

/// The precomputation in `dir` opened as the session opens it, its scene's warnings printed.
fn open(dir: &Path, lights: Option<&Path>) -> Result<Opened> {
    let opened = fenestra_session::relight::open(dir, lights).map_err(crate::flagged)?;
    for w in &opened.warnings {
        eprintln!("warning: {w}");
    }
    Ok(opened)
}

fn export(a: &ExportArgs) -> Result<()> {
    let Opened {
        store,
        animated,
        lights,
        inputs,
        ..
    } = open(&a.dir, a.lights.as_deref())?;
    if a.frame >= store.manifest.frames {
        bail!(
            "--frame {} is not a frame of the sequence (0 to {})",
            a.frame,
            store.manifest.frames - 1
        );
    }
    if a.output.extension().is_none_or(|e| e != "pbrt") {
        bail!("output {} must end in .pbrt", a.output.display());
    }
    let mut desc = animated.at(a.frame);
    desc.lights = lights.apply(&desc.lights);
    desc.defaults.width = store.manifest.width;
    desc.defaults.height = store.manifest.height;
    // Relighting sees each pixel through its centre: so does its ground truth (a box filter
    // a thousandth of a pixel wide), or edges would count as error.
    desc.camera.filter = PixelFilter::new(FilterShape::Box, fenestra_core::Vec2::splat(1e-3));
    fenestra_session::files::create_output_folder(&a.output)?;
    fenestra_session::files::Files::default()
        .inputs(&inputs, "input")
        .output(&a.output, "export")
        .folder(
            &fenestra_pbrt::export::data_folder(&a.output),
            "export's data folder",
        )
        .check()?;
    for f in fenestra_pbrt::export::write(&desc, &a.output)?.files {
        println!("wrote {}", f.display());
    }
    Ok(())
}

fn render(a: &RenderArgs) -> Result<()> {
    let Opened {
        store,
        animated,
        lights,
        ..
    } = open(&a.dir, a.lights.as_deref())?;
    let m = &store.manifest;
    let range = frame_range(a.frames.as_deref(), m.frames)?;
    let missing: Vec<u32> = range
        .clone()
        .filter(|&f| !store.frame_path(f).exists())
        .collect();
    if !missing.is_empty() {
        bail!(
            "{} of the frames asked for are not precomputed (first: {}): run `fenestra relight precompute` again to finish them",
            missing.len(),
            missing[0]
        );
    }
    std::fs::create_dir_all(&a.output)
        .with_context(|| format!("cannot create {}", a.output.display()))?;
    let mut player = Player::new(store, animated, a.light_samples, 0)?;
    let bar = frame_bar(range.len() as u64, a.quiet);
    let mut exposure = a.exposure;
    let (mut relight_s, mut frames_done) = (0.0, 0);
    for f in range {
        let relit = player.relight(f, &lights)?;
        relight_s += relit.seconds;
        frames_done += 1;
        let image = relit.image(a.indirect_only);
        // One exposure for the whole sequence (the first frame's), so frames do not flicker.
        let ev = *exposure.get_or_insert_with(|| image.auto_exposure_scale().log2());
        let exr = a.output.join(format!("frame-{f:04}.exr"));
        let metadata = BTreeMap::from([
            ("fenestra.relight.frame".to_string(), f.to_string()),
            ("fenestra.relight.exposure".to_string(), ev.to_string()),
        ]);
        image.write_exr(&exr, &metadata)?;
        image.write_png(&exr.with_extension("png"), Some(ev))?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    if !a.quiet {
        eprintln!(
            "relit {frames_done} frames in {:.3} s each (building the posed and lit scene, the gather samples' direct light, the transfer, direct light at the pixels; reading frame files and writing images excluded)",
            relight_s / frames_done.max(1) as f64
        );
    }
    println!("wrote {}", a.output.display());
    Ok(())
}

/// Largest request body the relighting server reads, bytes.
const MAX_REQUEST: u64 = 1 << 20;

/// Most lights a request may relight a frame under.
const MAX_LIGHTS: usize = 256;

fn serve(a: &ServeArgs) -> Result<()> {
    let Opened {
        store,
        animated,
        lights,
        ..
    } = open(&a.dir, a.lights.as_deref())?;
    let mut player = Player::new(store, animated, a.light_samples, a.cache_mb << 20)?;
    let m = player.store.manifest.clone();
    // The frames precomputed so far (an unfinished precomputation serves what it has).
    let available: Vec<u32> = (0..m.frames).filter(|&f| player.store.done(f)).collect();
    let Some(&first) = available.first() else {
        bail!(
            "{} holds no precomputed frame: run `fenestra relight precompute` first",
            a.dir.display()
        );
    };
    let exposure = match a.exposure {
        Some(ev) => ev,
        None => {
            let first = player.relight(first, &lights)?;
            first.image(false).auto_exposure_scale().log2()
        }
    };
    let (lo, hi) = frame_scene(&player.animated, first, None)?.scene.bounds();
    let camera: Vec<[f32; 3]> = (0..m.frames)
        .map(|f| player.animated.at(f).camera.position.to_array())
        .collect();
    let state = serde_json::json!({
        "frames": m.frames,
        "available": available,
        "width": m.width,
        "height": m.height,
        "zoom": (640 / m.width.max(1)).clamp(1, 4),
        "exposure": exposure,
        "lights": lights,
        "bounds": [lo.to_array(), hi.to_array()],
        "camera": camera,
    })
    .to_string();
    let server = tiny_http::Server::http(("127.0.0.1", a.port))
        .map_err(|e| anyhow!("cannot listen on 127.0.0.1:{}: {e}", a.port))?;
    let addr = server
        .server_addr()
        .to_ip()
        .ok_or_else(|| anyhow!("the server has no IP address"))?;
    // The address on stdout (scripts and tests read it), how to stop on stderr.
    println!("serving http://{addr}/");
    eprintln!(
        "relighting {} ({} of its {} frames precomputed, {}x{}); Ctrl-C stops",
        a.dir.display(),
        available.len(),
        m.frames,
        m.width,
        m.height
    );
    use std::io::Write;
    let _ = std::io::stdout().flush();
    let header = |k: &str, v: &str| {
        tiny_http::Header::from_bytes(k.as_bytes(), v.as_bytes())
            .map_err(|_| anyhow!("bad header {k}"))
    };
    for mut request in server.incoming_requests() {
        let url = request.url().split('?').next().unwrap_or("").to_string();
        let response = match (request.method(), url.as_str()) {
            (tiny_http::Method::Get, "/") => {
                tiny_http::Response::from_string(include_str!("relight_page.html"))
                    .with_header(header("Content-Type", "text/html; charset=utf-8")?)
            }
            (tiny_http::Method::Get, "/state") => tiny_http::Response::from_string(state.clone())
                .with_header(header("Content-Type", "application/json")?),
            (tiny_http::Method::Post, "/frame") => {
                let mut body = String::new();
                // {"frame": F, "lights": LIGHTS FILE}, checked as a lights file is; at most
                // MAX_REQUEST bytes and MAX_LIGHTS lights (one request must not hold the
                // server for minutes).
                let reader = std::io::Read::take(request.as_reader(), MAX_REQUEST + 1);
                let asked = std::io::Read::read_to_string(&mut { reader }, &mut body)
                    .map_err(|e| e.to_string())
                    .and_then(|n| {
                        if n as u64 > MAX_REQUEST {
                            Err(format!("request larger than {MAX_REQUEST} bytes"))
                        } else {
                            Ok(n)
                        }
                    })
                    .and_then(|_| {
                        serde_json::from_str::<serde_json::Value>(&body)
                            .map_err(|e| format!("bad request: {e}"))
                    })
                    .and_then(|v| {
                        let frame = v["frame"].as_u64().ok_or("bad request: no frame number")?;
                        let lights =
                            LightsFile::parse(&v["lights"].to_string(), "the page's lights")
                                .map_err(|e| e.to_string())?;
                        if lights.lights.len() > MAX_LIGHTS {
                            return Err(format!(
                                "at most {MAX_LIGHTS} lights, got {}",
                                lights.lights.len()
                            ));
                        }
                        Ok((frame.min(u32::MAX as u64) as u32, lights))
                    });
                let relit = asked.and_then(|(frame, lights)| {
                    player.relight(frame, &lights).map_err(|e| e.to_string())
                });
                match relit {
                    Ok(relit) => match relit.image(false).png(Some(exposure)) {
                        Ok(png) => tiny_http::Response::from_data(png)
                            .with_header(header("Content-Type", "image/png")?)
                            .with_header(header("X-Relight-Seconds", &relit.seconds.to_string())?),
                        Err(e) => {
                            tiny_http::Response::from_string(e.to_string()).with_status_code(500)
                        }
                    },
                    Err(e) => tiny_http::Response::from_string(e).with_status_code(400),
                }
            }
            _ => tiny_http::Response::from_string("not found").with_status_code(404),
        };
        // A page closed mid-answer is not the server's problem.
        let _ = request.respond(response);
    }
    Ok(())
}
