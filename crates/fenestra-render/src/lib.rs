//! Rendering for fenestra: BSDFs, lights and light selection, the film, the integrator seam
//! and the drivers that run integrators in parallel. Research systems live in their own
//! crates and plug in through [`Integrator`] (with [`render`] running it), the
//! [`NextEvent`](integrator::NextEvent) strategies of the shared path loop,
//! [`LightSampler`](light::LightSampler) and the block/pass driver
//! ([`driver::PassEstimator`]). docs/architecture.md shows how.
#![warn(missing_docs)]

pub mod bsdf;
pub mod control;
pub mod driver;
pub mod features;
pub mod film;
pub mod film_file;
pub mod integrator;
pub mod light;
pub mod merge;
pub mod options;
pub mod output;
pub mod path_sample;
pub mod registered;
pub mod registry;
pub mod render_scene;
pub mod sample_context;
pub mod settings;
pub mod splat;

pub use control::{NoProgress, Progress, RenderControl};
pub use fenestra_core::stats::{RayCounters, RenderStats};
pub use film::Film;
pub use integrator::{render, render_image, Integrator, IntegratorError};
pub use registered::register;
pub use registry::Registry;
pub use render_scene::RenderScene;
pub use settings::RenderSettings;
