//! A render fully specified and checked, ready to run: the scene, the integrator built from
//! the registry, the settings, and the part of the image and of the samples it takes.

use crate::error::{Error, Result, Setting};
use crate::files::Files;
use crate::registry::{registry, IntegratorChoice};
use crate::scene::LoadedScene;
use anyhow::Context;
use fenestra_core::hash::{debug_hash, Fnv64};
use fenestra_core::Rgb;
use fenestra_render::control::{PassHook, Progress, ProgressHook};
use fenestra_render::driver::BLOCK_SIZE;
use fenestra_render::features::FeaturePixel;
use fenestra_render::film::{Pixel, Window};
use fenestra_render::film_file::{FilmHeader, SampleRange};
use fenestra_render::integrator::{IntegratorError, Split, WorkMap};
use fenestra_render::{Film, Integrator, RenderControl, RenderScene, RenderSettings, RenderStats};
use fenestra_scene::{Backend, Scene, SceneDesc};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// An image size, checked: sides of 1 to 65,536 pixels, at most 2^27 pixels (the film keeps
/// 112 bytes per pixel: exact sums and squares in 128-bit integers, a count).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Resolution {
    pub width: u32,
    pub height: u32,
}

impl Resolution {
    /// `width` x `height`, if a film of that size can be made.
    pub fn new(width: u32, height: u32) -> Result<Self> {
        if width == 0 || height == 0 {
            return Err(Error::setting(
                Setting::Resolution,
                format!("{width}x{height} has no pixels: both sides must be at least 1"),
            ));
        }
        if width > 65536 || height > 65536 {
            return Err(Error::setting(
                Setting::Resolution,
                format!("{width}x{height} is too large: at most 65536 pixels a side"),
            ));
        }
        if u64::from(width) * u64::from(height) > 1 << 27 {
            return Err(Error::setting(
                Setting::Resolution,
                format!("{width}x{height} is too large: at most 134 million pixels (about 15 GB of film)"),
            ));
        }
        Ok(Resolution { width, height })
    }
}

/// Columns x0 to x1-1 and rows y0 to y1-1 of an image: a tile of a render split across
/// machines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Crop {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl std::fmt::Display for Crop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{},{},{},{}", self.x0, self.y0, self.x1, self.y1)
    }
}

impl Crop {
    /// The window of a `width` x `height` image it covers; `split` says whether its corners
    /// must lie on the block grid.
    pub fn window(self, width: u32, height: u32, split: Split) -> Result<Window> {
        let Crop { x0, y0, x1, y1 } = self;
        if !(x0 < x1 && y0 < y1 && x1 <= width && y1 <= height) {
            return Err(Error::setting(
                Setting::Crop,
                format!("{self} must be X0,Y0,X1,Y1 with X0 < X1 <= {width} and Y0 < Y1 <= {height} (the image is {width}x{height})"),
            ));
        }
        let on_grid = |v: u32, edge: u32| v.is_multiple_of(BLOCK_SIZE) || v == edge;
        if split == Split::BlockTiles
            && !(on_grid(x0, 0) && on_grid(y0, 0) && on_grid(x1, width) && on_grid(y1, height))
        {
            return Err(Error::setting(
                Setting::Crop,
                format!("{self}: this integrator renders 8x8 pixel blocks as wholes: the corners must be multiples of {BLOCK_SIZE} (or the image's edge)"),
            ));
        }
        Ok(Window {
            full_width: width,
            full_height: height,
            x0,
            y0,
            x1,
            y1,
        })
    }
}

/// What a render is asked to be beside its scene.
#[derive(Clone, Debug, Default)]
pub struct JobSpec {
    /// The integrator and its options.
    pub integrator: IntegratorChoice,
    /// Samples per pixel (default: the scene's, or unlimited with `time`).
    pub spp: Option<u32>,
    /// Seconds to render for (with `spp`: whichever comes first).
    pub time: Option<f64>,
    pub seed: u64,
    /// Image size (default: the scene's).
    pub resolution: Option<Resolution>,
    /// Whether to take denoising features (albedo, normal) beside the samples.
    pub features: bool,
}

/// What a finished (or interrupted) render made.
pub struct Rendered {
    pub stats: RenderStats,
    pub film: Film,
    /// Pictures of the integrator's own work, if it makes any.
    pub maps: Vec<WorkMap>,
}

/// A render fully specified and checked, ready to run.
pub struct Job {
    desc: SceneDesc,
    /// The hash of the scene's content that its images carry.
    scene_content: String,
    /// What the render reads: scene files, a portals file.
    pub inputs: Files,
    width: u32,
    height: u32,
    integrator: Box<dyn Integrator>,
    /// Seed, sample range and time limit.
    pub settings: RenderSettings,
    /// Whether a sample count was asked for (which a sample range replaces).
    spp_given: bool,
    /// The part of the image to render (all of it unless cut).
    window: Window,
    /// Whether the film takes denoising features.
    features: bool,
}

impl Job {
    /// A render of `scene` as `spec` says, checked and with its integrator built.
    pub fn new(scene: LoadedScene, spec: &JobSpec) -> Result<Job> {
        if let Some(t) = spec.time {
            if !(t.is_finite() && t > 0.0) {
                return Err(Error::setting(
                    Setting::Time,
                    format!("must be a positive number of seconds, got {t}"),
                ));
            }
        }
        if spec.spp == Some(0) {
            return Err(Error::setting(Setting::Spp, "must be at least 1"));
        }
        let LoadedScene {
            source,
            desc,
            files,
            ..
        } = scene;
        let scene_content = scene_content(&source, &files)?;
        let mut inputs = Files::default();
        inputs.inputs(&files, "scene file");
        if let Some(p) = spec.integrator.portals_file() {
            inputs.input(Path::new(p), "portals file");
        }
        let (width, height) = spec
            .resolution
            .map_or((desc.defaults.width, desc.defaults.height), |r| {
                (r.width, r.height)
            });
        let integrator = registry()
            .build(&spec.integrator.name, &spec.integrator.params, &desc)
            .map_err(|e| match e {
                IntegratorError::Option(e) => Error::Option(e),
                e => Error::Failed(e.into()),
            })?;
        if let (Some(spp), Split::BlockTiles) = (spec.spp, integrator.split()) {
            return Err(Error::setting(
                Setting::Spp,
                format!("{spp} would not steer it; set {{ias.threshold}}, or {{time}}: {} decides how many samples each pixel takes (until the pixel's relative variance is below its threshold)", integrator.name()),
            ));
        }
        let spp = match spec.time {
            Some(_) => spec.spp.unwrap_or(u32::MAX),
            None => spec.spp.unwrap_or(desc.defaults.spp),
        };
        let settings = RenderSettings {
            first_sample: 0,
            spp,
            time_limit: spec.time,
            seed: spec.seed,
        };
        Ok(Job {
            desc,
            scene_content,
            inputs,
            width,
            height,
            integrator,
            settings,
            spp_given: spec.spp.is_some(),
            window: Window::full(width, height),
            features: spec.features,
        })
    }

    /// The scene it renders.
    pub fn desc(&self) -> &SceneDesc {
        &self.desc
    }

    /// The image's size.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The integrator's name.
    pub fn integrator_name(&self) -> &str {
        self.integrator.name()
    }

    /// How the integrator's renders split into pieces.
    pub fn split(&self) -> Split {
        self.integrator.split()
    }

    /// Everything that changes the picture but the sample count and the window: what the
    /// pieces of a split render share.
    fn picture_key(&self, backend: Backend) -> u64 {
        debug_hash(&(
            &self.desc,
            self.integrator.name(),
            self.integrator.settings().to_string(),
            self.width,
            self.height,
            self.settings.seed,
            backend.name(),
            env!("CARGO_PKG_VERSION"),
        ))
    }

    /// Everything that changes the picture: the reference cache key.
    pub fn key(&self, backend: Backend) -> u64 {
        debug_hash(&(self.picture_key(backend), self.settings.spp))
    }

    /// Makes the job one piece of a split render: the sample indices `samples` of every
    /// pixel and the tile `crop`. Returns what the piece's film-state file says of it, if it
    /// is one.
    pub fn cut(
        &mut self,
        samples: Option<SampleRange>,
        crop: Option<Crop>,
        backend: Backend,
    ) -> Result<Option<FilmHeader>> {
        if samples.is_none() && crop.is_none() {
            return Ok(None);
        }
        let split = self.integrator.split();
        let piece = if samples.is_some() {
            Setting::Samples
        } else {
            Setting::Crop
        };
        if split == Split::Whole {
            return Err(Error::setting(
                piece,
                format!("cuts a piece of a render, and {} learns from, or builds caches from, every pixel's samples: it renders whole, not in pieces", self.integrator.name()),
            ));
        }
        if let Some(r) = samples {
            if r.start >= r.end {
                return Err(Error::setting(
                    Setting::Samples,
                    format!("{r} is empty: the first index must come before the end"),
                ));
            }
            if self.spp_given {
                return Err(Error::setting(
                    Setting::Samples,
                    format!("{r} says how many samples to take: not with {{spp}}"),
                ));
            }
            if split == Split::BlockTiles {
                return Err(Error::setting(
                    Setting::Samples,
                    format!("cannot cut {}'s samples: it decides how many samples each pixel takes; split it by tiles ({{crop}})", self.integrator.name()),
                ));
            }
            self.settings.first_sample = r.start;
            self.settings.spp = r.end - r.start;
        }
        if let Some(c) = crop {
            if split == Split::Samples {
                return Err(Error::setting(
                    Setting::Crop,
                    format!("cannot cut a tile of {}'s render: its light paths bring light to every part of the image; split it by sample ranges ({{samples}})", self.integrator.name()),
                ));
            }
            self.window = c.window(self.width, self.height, split)?;
        }
        let samples = (split != Split::BlockTiles).then_some(SampleRange {
            start: self.settings.first_sample,
            end: self.settings.first_sample + self.settings.spp,
        });
        Ok(Some(FilmHeader {
            key: format!("{:016x}", self.picture_key(backend)),
            samples,
            window: self.window,
            stats: RenderStats::default(),
            features: self.features,
        }))
    }

    /// Builds the scene, prepares the integrator and renders on a pool of `threads` workers
    /// (all cores by default), until done or `cancel` is set (what was rendered is kept);
    /// `hook` after every pass, `watch` whenever the film holds more of the image.
    pub fn run(
        self,
        threads: Option<usize>,
        backend: Backend,
        cancel: &AtomicBool,
        progress: &dyn Progress,
        hook: Option<PassHook>,
        watch: Option<ProgressHook>,
    ) -> Result<Rendered> {
        film_fits_in_memory(self.window, self.features)?;
        let pool = crate::thread_pool(threads)?;
        let Job {
            desc,
            scene_content,
            mut integrator,
            settings,
            window,
            features,
            ..
        } = self;
        pool.install(|| -> Result<_> {
            let scene = Scene::build(desc, backend).context("invalid scene")?;
            let scene = RenderScene::new(scene);
            let mut film = Film::cropped(window);
            if features {
                film = film.with_features();
            }
            let mut control = RenderControl::new(cancel, progress);
            control.on_pass = hook;
            control.on_progress = watch;
            let stats = fenestra_render::render(
                integrator.as_mut(),
                &scene,
                &mut film,
                &settings,
                &control,
            )
            .map_err(anyhow::Error::from)?;
            let stats = RenderStats {
                scene_content,
                ..stats
            };
            mostly_kept(&film, &stats)?;
            Ok(Rendered {
                stats,
                film,
                maps: integrator.work_maps(),
            })
        })
    }
}

/// Refuses a render that dropped most of its samples (non-finite, or beyond the film's
/// 2^31 in a channel): its image is black or nearly, and no picture of the scene. Samples
/// kept are the film's, or the camera rays less those dropped where the film holds each
/// pixel's estimate as two samples (integrators that finish blocks whole).
fn mostly_kept(film: &Film, stats: &RenderStats) -> Result<()> {
    let dropped = stats.rays.dropped;
    let in_film: u64 = film.pixels.iter().map(|p| u64::from(p.count)).sum();
    let kept = in_film.max(stats.rays.camera.saturating_sub(dropped));
    if dropped > kept {
        return Err(anyhow::anyhow!(
            "{dropped} of {} samples ({:.0}%) were dropped as non-finite or beyond 2^31 in a \
             channel: the scene's light is brighter than the film can add up (a light, \
             emission or environment strength near the 3.4e38 of 32-bit floats?)",
            dropped + kept,
            100.0 * dropped as f64 / (dropped + kept) as f64
        )
        .into());
    }
    Ok(())
}

/// The hash of a scene's content: its files' bytes, in the order they were read (a
/// built-in scene, which has none: its name and fenestra's version).
fn scene_content(scene: &str, files: &[PathBuf]) -> anyhow::Result<String> {
    let mut hash = Fnv64::default();
    if files.is_empty() {
        hash.update(scene.as_bytes());
        hash.update(env!("CARGO_PKG_VERSION").as_bytes());
    }
    let mut buffer = vec![0; 1 << 16];
    for path in files {
        let mut file = std::fs::File::open(path)
            .with_context(|| format!("reading {} again", path.display()))?;
        loop {
            let n = std::io::Read::read(&mut file, &mut buffer)
                .with_context(|| format!("reading {} again", path.display()))?;
            if n == 0 {
                break;
            }
            hash.update(&buffer[..n]);
        }
    }
    Ok(format!("{:016x}", hash.finish()))
}

/// Refuses a film (with the mean and variance images written from it, and room for the
/// EXR writer's copy) larger than the memory the process can get (the machine's, or what
/// `ulimit -v` leaves), before allocating it: naming both figures.
fn film_fits_in_memory(window: Window, features: bool) -> anyhow::Result<()> {
    let (w, h) = (window.x1 - window.x0, window.y1 - window.y0);
    // With features: their sums, and their two images.
    let features = match features {
        true => std::mem::size_of::<FeaturePixel>() + 2 * std::mem::size_of::<Rgb>(),
        false => 0,
    };
    let per_pixel = std::mem::size_of::<Pixel>() + 4 * std::mem::size_of::<Rgb>() + features;
    let needed = u64::from(w) * u64::from(h) * per_pixel as u64;
    fenestra_core::memory::ensure(needed, || format!("a {w}x{h} film")).map_err(|e| {
        anyhow::anyhow!(
            "{e}: render a smaller resolution, or tiles of it (a crop) merged afterwards"
        )
    })
}
