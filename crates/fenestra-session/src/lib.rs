//! A fenestra render session as a library: what every front end (the `fenestra` command line,
//! the Python module, the Blender add-on through them, a program that embeds fenestra) stands
//! on. A scene is asked for as a typed [`SceneRequest`] and [`load`]ed; a render is a
//! [`JobSpec`] made into a checked [`Job`] (its integrator built from the [`registry`] of
//! every integrator and light sampler), optionally cut into a piece of a split render, and
//! run; its outputs follow the [`files`] rules (no output replaces an input).
//!
//! ```no_run
//! use fenestra_session::{render, JobSpec, SceneRequest};
//!
//! let spec = JobSpec { spp: Some(16), ..JobSpec::default() };
//! let done = render(&SceneRequest::new("builtin:cornell-box"), &spec)?;
//! println!("{}", done.stats.summary());
//! # Ok::<(), fenestra_session::Error>(())
//! ```
//!
//! Errors are typed ([`Error`]): a refused setting says which ([`Setting`]), and each front
//! end words it by its own names ([`Error::worded`]: `--sun-time` or `sun_time`).

pub mod denoise;
pub mod error;
pub mod files;
pub mod job;
pub mod registry;
pub mod relight;
pub mod scene;

pub use error::{Error, Result, Setting, Style};
pub use job::{Crop, Job, JobSpec, Rendered, Resolution};
pub use registry::{catalogue, registry, IntegratorChoice, DEFAULT_INTEGRATOR};
pub use scene::{load, Lighting, LoadedScene, Placement, SceneRequest, SkyRequest, SunPlace};

use fenestra_render::control::NoProgress;
use std::sync::atomic::AtomicBool;

/// A rayon pool with `threads` workers (all cores by default).
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(t) = threads {
        if t == 0 {
            return Err(Error::setting(Setting::Threads, "must be at least 1"));
        }
        pool = pool.num_threads(t);
    }
    Ok(pool.build().map_err(anyhow::Error::from)?)
}

/// Loads the scene `request` asks for and renders it as `spec` says, on every core with the
/// default ray-query backend, to the end.
pub fn render(request: &SceneRequest, spec: &JobSpec) -> Result<Rendered> {
    let job = Job::new(load(request)?, spec)?;
    job.run(
        None,
        Default::default(),
        &AtomicBool::new(false),
        &NoProgress,
        None,
        None,
    )
}
