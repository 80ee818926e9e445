//! `fenestra render` and `fenestra reference`.

use crate::flagged;
use crate::integrators::IntegratorArgs;
use crate::support::denoise::DenoiseArgs;
use crate::support::progress::{Bar, Lines};
use crate::support::{interrupt, pieces, scene_arg};
use anyhow::{bail, Context, Result};
use clap::Args;
use fenestra_core::image::Image;
use fenestra_core::stats::ConvergencePoint;
use fenestra_eval::metrics;
use fenestra_render::control::{PassHook, Progress, ProgressHook};
use fenestra_render::film_file::FilmHeader;
use fenestra_render::integrator::{Split, WorkMap};
use fenestra_render::output::{self, Extras, FeatureLayout};
use fenestra_render::{Film, RenderStats};
use fenestra_scene::Backend;
use fenestra_session::files::{self, check_exr, render_outputs, Beside};
use fenestra_session::{Job, JobSpec, Rendered, Resolution};
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
    pub(crate) bvh: Option<Backend>,
    /// PNG exposure in stops (default: automatic, log-average luminance to middle grey).
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) exposure: Option<f32>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub(crate) json: bool,
    /// No progress bar.
    #[arg(short, long)]
    pub(crate) quiet: bool,
    /// Progress as lines `progress DONE TOTAL SECONDS` on stderr instead of a bar (TOTAL is
    /// `-` when a time limit, not a sample count, ends the render), at most five a second:
    /// for programs that run fenestra, such as the Blender add-on.
    #[arg(long, conflicts_with = "quiet")]
    pub(crate) progress_lines: bool,
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
    /// Also write OUT.var.exr, the per-pixel variance of the mean; renders with light paths
    /// (lp_lt, lt) also write OUT.light-paths.exr and .png, the light those brought (their
    /// variance as the EXR's layer `variance`).
    #[arg(long)]
    variance: bool,
    /// Write the image so far (EXR, PNG, JSON with "snapshot" in its extra figures, and the
    /// variance with --variance) at most every SECONDS, after a pass (ias: after a block),
    /// atomically and under the final files' names, so that a long render can be watched;
    /// the final image is the same with or without.
    #[arg(long, value_name = "SECONDS")]
    snapshot_every: Option<f64>,
    /// Also write pictures of the integrator's own work, if it makes any (ias: passes,
    /// shadow rays, visible share, clusters per cut, anti-aliasing regions per pixel) into
    /// the folder OUT-maps, as false-colour PNGs with their scales in scales.json.
    #[arg(long)]
    maps: bool,
    /// Render only the sample indices A to B-1 of every pixel: one piece of a render split
    /// across machines. Writes OUT.film too, the exact sums that `fenestra merge` adds into
    /// the image one render of all the samples makes. Not with --spp or --time.
    #[arg(long, value_name = "A..B")]
    samples: Option<String>,
    /// Render only columns X0 to X1-1 and rows Y0 to Y1-1 (a tile of a render split across
    /// machines); writes OUT.film for `fenestra merge`. ias needs corners on the 8-pixel
    /// block grid (or the image's edge).
    #[arg(long, value_name = "X0,Y0,X1,Y1")]
    crop: Option<String>,
    /// Take denoising features beside the samples: each pixel's albedo and shading normal
    /// at the first surface that is not a mirror or smooth glass. WHERE: layers (default:
    /// the EXR's layers `albedo` (R, G, B) and `normal` (X, Y, Z)) or files (OUT.albedo.exr
    /// and OUT.normal.exr beside a plain OUT.exr, for tools that read one image a file).
    /// --denoise takes them too (as layers unless told).
    #[arg(long, value_name = "WHERE", num_args = 0..=1, default_missing_value = FeatureLayout::default().name())]
    features: Option<FeatureLayout>,
    #[command(flatten)]
    denoise: DenoiseArgs,
    /// Output EXR; the PNG and JSON sidecar are written beside it.
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    opts: RenderOpts,
}

/// Reads WxH (the size checks are the session's).
pub fn parse_resolution(s: &str) -> Result<Resolution> {
    let bad = || {
        anyhow::anyhow!("bad resolution '{s}': expected WxH with positive integers, e.g. 512x512")
    };
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let side = |v: &str| -> Result<u32> {
        let v = v.trim();
        if v.is_empty() || !v.bytes().all(|b| b.is_ascii_digit()) {
            bail!(bad());
        }
        match v.parse::<u32>() {
            Ok(0) => bail!(bad()),
            Ok(n) => Ok(n),
            Err(_) => bail!("resolution '{s}' is too large: at most 65536 pixels a side"),
        }
    };
    Resolution::new(side(w)?, side(h)?).map_err(flagged)
}

impl RenderOpts {
    /// Checks every argument and builds the integrator before the (possibly long) scene
    /// build; the render takes denoising features if `features`.
    pub(crate) fn job(&self, time: Option<f64>, features: bool) -> Result<Job> {
        let resolution = self
            .resolution
            .as_deref()
            .map(parse_resolution)
            .transpose()?;
        if let Some(e) = self.exposure.filter(|e| !e.is_finite()) {
            bail!("--exposure must be a finite number of stops, got {e}");
        }
        let spec = JobSpec {
            integrator: self.integrator.0.clone(),
            spp: self.spp,
            time,
            seed: self.seed,
            resolution,
            features,
        };
        let loaded = scene_arg::load(&self.scene, &self.scene_options)?;
        Job::new(loaded, &spec).map_err(flagged)
    }

    /// [`Job::run`] with this command's threads and backend, Ctrl-C stopping it cleanly
    /// and a progress bar.
    pub(crate) fn run(
        &self,
        job: Job,
        hook: Option<PassHook>,
        watch: Option<ProgressHook>,
    ) -> Result<Rendered> {
        let cancel = interrupt::on_ctrl_c("writing the samples taken so far");
        let bar = Bar::new(self.quiet || self.json || self.progress_lines);
        let lines = Lines::default();
        let progress: &dyn Progress = if self.progress_lines { &lines } else { &bar };
        let done = job.run(
            self.threads,
            self.bvh.unwrap_or_default(),
            &cancel,
            progress,
            hook,
            watch,
        );
        bar.finish();
        done.map_err(flagged)
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

/// What `fenestra split` needs to know of a render given as `fenestra render` arguments.
pub struct RenderShape {
    /// The scene's name.
    pub scene: String,
    /// The integrator's name.
    pub integrator: String,
    /// Samples per pixel (asked for, or the scene's).
    pub spp: u32,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// How the integrator's renders split.
    pub split: Split,
}

/// Checks `args` (a scene and `fenestra render` options, without an output) as `render`
/// would, loading the scene, and says what the render would be.
pub fn shape(args: &[String]) -> Result<RenderShape> {
    #[derive(clap::Parser)]
    #[command(name = "fenestra render", no_binary_name = true)]
    struct Render {
        #[command(flatten)]
        args: RenderArgs,
    }
    for (flag, why) in [
        ("-o", "the job names the parts' outputs"),
        ("--output", "the job names the parts' outputs"),
        ("--time", "the parts take fixed samples"),
        ("--samples", "the job cuts the samples"),
        ("--crop", "the job cuts the tiles"),
        ("--reference", "measure the merged image instead"),
    ] {
        if args
            .iter()
            .any(|a| a == flag || a.starts_with(&format!("{flag}=")))
        {
            bail!("{flag} is not for split ({why})");
        }
    }
    let parsed = <Render as clap::Parser>::try_parse_from(
        args.iter().map(String::as_str).chain(["-o", "split.exr"]),
    )?;
    let job = parsed.args.opts.job(None, false)?;
    let (width, height) = job.size();
    Ok(RenderShape {
        scene: job.desc().name.clone(),
        integrator: job.integrator_name().to_string(),
        spp: job.settings.spp,
        width,
        height,
        split: job.split(),
    })
}

/// Renders; returns whether the render was interrupted (its partial result is written).
pub fn run(args: RenderArgs) -> Result<bool> {
    check_exr(&args.output)?;
    if let Some(t) = args.target_rel_mse {
        if !(t.is_finite() && t > 0.0) {
            bail!("--target-rel-mse must be positive, got {t}");
        }
    }
    if let Some(t) = args.snapshot_every {
        if !(t.is_finite() && t > 0.0) {
            bail!("--snapshot-every must be a positive number of seconds, got {t}");
        }
        if args.samples.is_some() || args.crop.is_some() {
            bail!("--snapshot-every watches whole renders: a piece is merged from its .film (watch the merged render instead)");
        }
    }
    args.denoise.check()?;
    let features = args.features.is_some() || args.denoise.denoise.is_some();
    let mut job = args.opts.job(args.time, features)?;
    let samples = args.samples.as_deref().map(pieces::parse_samples);
    let crop = args.crop.as_deref().map(pieces::parse_crop);
    let piece = job
        .cut(
            samples.transpose()?,
            crop.transpose()?,
            args.opts.bvh.unwrap_or_default(),
        )
        .map_err(flagged)?;
    if piece.is_some() && args.time.is_some() {
        bail!("a piece of a split render takes a fixed set of samples: not with --time");
    }
    if piece.is_some() && args.reference.is_some() {
        bail!("--reference measures whole renders: measure the merged image instead");
    }
    let mut files = std::mem::take(&mut job.inputs);
    if let Some(r) = &args.reference {
        files.input(r, "reference");
    }
    let maps_dir = maps_folder(&args.output);
    if args.maps {
        files.folder(&maps_dir, "work maps folder");
    }
    // An interruption (or a snapshot) over a complete render writes beside it.
    let beside = Beside {
        variance: args.variance,
        state: piece.is_some(),
        denoised: args.denoise.denoise.is_some(),
        feature_files: args.features == Some(FeatureLayout::Files),
    };
    render_outputs(&mut files, &args.output, beside);
    render_outputs(&mut files, &files::interrupted_path(&args.output), beside).check()?;
    let reference = match &args.reference {
        Some(p) => {
            let r = Image::read(p)?;
            let (width, height) = job.size();
            if (r.width, r.height) != (width as usize, height as usize) {
                bail!(
                    "reference {} is {}x{}, the render {width}x{height}",
                    p.display(),
                    r.width,
                    r.height,
                );
            }
            Some(r)
        }
        None => None,
    };
    // Snapshots go where an interrupted render would: never over a complete render.
    let snapshots = args.snapshot_every.map(|every| Snapshots {
        every,
        output: args.output.clone(),
        like: RenderStats {
            scene: job.desc().name.clone(),
            integrator: job.integrator_name().to_string(),
            seed: job.settings.seed,
            ..Default::default()
        },
        state: Mutex::new(SnapshotState {
            last_s: f64::NEG_INFINITY,
            written: 0,
            at: None,
        }),
    });
    // Convergence: metrics against the reference after every pass.
    let curve = Mutex::new(Vec::new());
    let watch = |film: &Film, time_s: f64| {
        if let Some(s) = &snapshots {
            s.write_if_due(film, time_s, &args);
        }
    };
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
                light_path_share: film.light_path_share(),
                light_path_variance_share: film.light_path_variance_share(),
            });
        }
        args.target_rel_mse.is_none_or(|t| m.rel_mse > t)
    };
    let watch = snapshots.as_ref().map(|_| &watch as ProgressHook);
    let Rendered {
        mut stats,
        film,
        maps,
    } = args.opts.run(job, Some(&hook), watch)?;
    if stats.interrupted && stats.spp_max == 0 {
        // Stopped before the first sample (while the scene was being built): a black image
        // would only replace whatever was there.
        eprintln!("interrupted before any sample: nothing written");
        return Ok(true);
    }
    stats.convergence = curve.into_inner().unwrap_or_default();
    let output = where_to_write(&args.output, stats.interrupted);
    if let Some(s) = snapshots {
        stats.extra.insert("snapshots".into(), s.written() as f64);
        s.remove_beside(&args.output, &output);
    }
    let denoised = args.denoise.apply(&film, &mut stats)?;
    let state = piece.map(|header| FilmHeader {
        stats: stats.clone(),
        ..header
    });
    let extras = Extras {
        features: args.features.unwrap_or_default(),
        exposure: args.opts.exposure,
        variance: args.variance,
        state: state.as_ref(),
        denoised: denoised.as_ref(),
    };
    output::write_render(&output, &film, &stats, &extras)?;
    args.opts.report(&output, &stats)?;
    if args.maps {
        write_maps(&maps_dir, &maps, film.width, film.height, &stats.integrator)?;
    }
    Ok(stats.interrupted)
}

/// [`files::where_to_write`], saying where an interrupted render goes instead.
fn where_to_write(output: &Path, interrupted: bool) -> PathBuf {
    let (path, note) = files::where_to_write(output, interrupted);
    if let Some(note) = note {
        eprintln!("{note}");
    }
    path
}

/// `--snapshot-every`: the image so far, written when the film holds more of it (after a
/// pass, or a block of an integrator that finishes blocks whole) and the interval has passed.
struct Snapshots {
    every: f64,
    /// The render's OUT.exr.
    output: PathBuf,
    /// The render's statistics that a snapshot's sidecar repeats.
    like: RenderStats,
    state: Mutex<SnapshotState>,
}

/// What snapshots have done so far.
struct SnapshotState {
    /// When the last one was written.
    last_s: f64,
    /// How many were.
    written: u32,
    /// Where the last went: each goes where an interrupted render would at the time it is
    /// written (OUT.exr, or beside a complete render there, which another render may have
    /// finished since the last).
    at: Option<PathBuf>,
}

impl Snapshots {
    /// Writes a snapshot of `film` at `time_s` if the interval has passed since the last;
    /// a snapshot that cannot be written is said and the render goes on.
    fn write_if_due(&self, film: &Film, time_s: f64, args: &RenderArgs) {
        let Ok(mut state) = self.state.lock() else {
            return;
        };
        if time_s - state.last_s < self.every {
            return;
        }
        let (spp, spp_max) = film.sample_count_range();
        let mut stats = RenderStats {
            width: film.width,
            height: film.height,
            spp,
            spp_max,
            time_s,
            interrupted: true,
            ..self.like.clone()
        };
        stats.extra.insert("snapshot".into(), 1.0);
        let (to, note) = files::where_to_write(&self.output, true);
        if let Some(note) = note.filter(|_| state.at.as_ref() != Some(&to)) {
            eprintln!("{note}");
        }
        let denoised = match args.denoise.apply(film, &mut stats) {
            Ok(image) => image,
            Err(e) => {
                eprintln!("warning: snapshot not denoised ({e})");
                None
            }
        };
        let extras = Extras {
            features: args.features.unwrap_or_default(),
            exposure: args.opts.exposure,
            variance: args.variance,
            state: None,
            denoised: denoised.as_ref(),
        };
        let written = output::write_render(&to, film, &stats, &extras);
        // Not again before the next interval, whether written or not.
        state.last_s = time_s;
        match written {
            Ok(()) => {
                state.written += 1;
                state.at = Some(to);
            }
            Err(e) => eprintln!("warning: snapshot not written ({e}); the render goes on"),
        }
    }

    /// How many were written.
    fn written(&self) -> u32 {
        self.state.lock().map_or(0, |s| s.written)
    }

    /// Removes the last snapshot's files if they went beside `output` and the render's own
    /// files went elsewhere (the snapshot of a finished render is stale).
    fn remove_beside(&self, output: &Path, written_to: &Path) {
        let Some(at) = self.state.lock().ok().and_then(|s| s.at.clone()) else {
            return;
        };
        if at == written_to || at == output {
            return;
        }
        let (png, json) = output::companion_paths(&at);
        let denoised = output::denoised_path(&at);
        let light_paths = output::light_paths_path(&at);
        let beside = [
            png,
            json,
            output::variance_path(&at),
            denoised.with_extension("png"),
            light_paths.with_extension("png"),
            light_paths,
        ];
        for f in [at.clone(), denoised].into_iter().chain(beside) {
            let _ = std::fs::remove_file(f);
        }
    }
}

/// Where `--maps` writes for OUT.exr: the folder OUT-maps beside it.
fn maps_folder(exr: &Path) -> PathBuf {
    let stem = exr
        .file_stem()
        .map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
    exr.with_file_name(format!("{stem}-maps"))
}

/// Writes each work map as a false-colour PNG NAME.png (inferno, from 0 to the map's
/// largest value), its values as NAME.exr (grey) and, in scales.json, what each shows and its largest value; each file
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
        // The values themselves, for computing with (`fenestra compare --mask`).
        let mut values = fenestra_core::image::Image::new(width as usize, height as usize);
        for (p, &v) in values.pixels.iter_mut().zip(&m.values) {
            *p = fenestra_core::Rgb::splat(v);
        }
        values.write_exr(&dir.join(format!("{}.exr", m.name)), &Default::default())?;
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
