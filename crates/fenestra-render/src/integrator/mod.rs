//! The integrator seam. An integrator is built from its own options (by a program, through
//! a [`Registry`](crate::registry::Registry)), prepared on a scene (pre-passes, caches,
//! estimation: [`Integrator::prepare`]) and then renders a whole image, usually through one
//! of the [drivers](crate::driver). [`render`] does both and times them together.
//!
//! Path tracers share one path loop ([`PathTracer`]) and differ in their next-event
//! strategy ([`NextEvent`]): none (`hf`), light sampling (`af_hf`), and strategies of the
//! research crates (light through openings, learned light samplers).

mod light_rays;
mod light_sampling;
mod next_event;
mod path;
mod path_densities;
mod path_options;

pub use light_rays::{
    beyond_glass, trace_probes, trace_shadows, Beyond, LightRays, ProbeRay, ShadowRay,
    MAX_REFRACTIONS,
};
pub use light_sampling::LightNextEvent;
pub use next_event::{sides_agree, Found, NextEvent, NoNextEvent, Scattered, Shading};
pub use path::{Gather, NoGather, PathTracer, Start};
pub use path_densities::{
    pixel_density, seen_density, CameraSide, FirstVertex, LightPaths, LightSide,
};
pub use path_options::{Mis, PathConfig, PathOptions, Roulette, Sides};

use crate::control::RenderControl;
use crate::film::Film;
use crate::light::LightSelection;
use crate::render_scene::RenderScene;
use crate::settings::RenderSettings;
use fenestra_core::stats::RenderStats;

/// Why an integrator cannot be built or prepared.
#[derive(Debug, thiserror::Error)]
pub enum IntegratorError {
    /// No integrator has this name.
    #[error("unknown integrator '{name}' (available: {available})")]
    Unknown {
        /// The name asked for.
        name: String,
        /// The registered names, comma-separated.
        available: String,
    },
    /// An option is out of range or contradicts another.
    #[error("{0}")]
    Options(String),
    /// An option cannot take its value.
    #[error(transparent)]
    Option(#[from] crate::options::OptionError),
    /// Preparation failed (a research crate's own error).
    #[error(transparent)]
    Prepare(Box<dyn std::error::Error + Send + Sync>),
}

/// A picture an integrator made of its own work: one value per pixel, row-major.
#[derive(Clone, Debug)]
pub struct WorkMap {
    /// File name without extension (`passes`).
    pub name: &'static str,
    /// What the values are, for people (`passes per pixel`).
    pub what: &'static str,
    /// The values.
    pub values: Vec<f32>,
}

/// How a render can be cut into pieces that render apart and merge exactly (scale-out).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Split {
    /// By sample ranges ([`RenderSettings::first_sample`]) or by tiles of any size.
    SamplesOrTiles,
    /// Only by tiles whose corners lie on the 8x8 block grid: integrators that decide how
    /// many samples each pixel of a block takes.
    BlockTiles,
    /// Only by sample ranges: integrators with light paths, whose splats land anywhere in the
    /// image (a tile would miss what other tiles' light paths bring to its pixels).
    Samples,
    /// Not at all: integrators whose every pixel depends on the whole render (caches built
    /// from all pixels' samples), so that no piece renders as it would in the single render.
    Whole,
}

/// A way of rendering an image.
pub trait Integrator: Send + Sync {
    /// The name it is known by (`af_hf`).
    fn name(&self) -> &str;

    /// Every setting that changes the picture: written to the sidecar and part of the
    /// reference-cache key.
    fn settings(&self) -> serde_json::Value;

    /// Work done once per scene before rendering (pre-passes, caches, estimation); it
    /// counts in the render's total time (`RenderStats::time_s`, with `prepare_s` its share;
    /// time limits count rendering only). May report through `control.progress` and stop
    /// early when `control` is cancelled.
    fn prepare(
        &mut self,
        _scene: &RenderScene,
        _control: &RenderControl,
    ) -> Result<(), IntegratorError> {
        Ok(())
    }

    /// Pictures of its own work in the last render (seed 004's passes per pixel, ...), one
    /// value per pixel, row-major; none by default.
    fn work_maps(&self) -> Vec<WorkMap> {
        Vec::new()
    }

    /// How its renders split across machines.
    fn split(&self) -> Split {
        Split::SamplesOrTiles
    }

    /// Renders the film's window of the image (all of it, unless cropped), once prepared.
    fn render(
        &self,
        scene: &RenderScene,
        film: &mut Film,
        settings: &RenderSettings,
        control: &RenderControl,
    ) -> RenderStats;
}

/// Prepares `integrator` on `scene`, then renders: the statistics' time covers both, from
/// the control's creation, with the preparation's share in `prepare_s`; a time limit covers
/// both too.
pub fn render(
    integrator: &mut dyn Integrator,
    scene: &RenderScene,
    film: &mut Film,
    settings: &RenderSettings,
    control: &RenderControl,
) -> Result<RenderStats, IntegratorError> {
    let control = &RenderControl {
        time_limit: settings.time_limit,
        image_size: Some((film.window.full_width, film.window.full_height)),
        ..*control
    };
    let before = control.elapsed();
    integrator.prepare(scene, control)?;
    let prepare_s = control.elapsed() - before;
    let mut stats = integrator.render(scene, film, settings, control);
    stats.integrator = integrator.name().to_string();
    stats.settings = integrator.settings();
    stats.prepare_s = prepare_s;
    stats.time_s = control.elapsed();
    stats.derive_rates();
    Ok(stats)
}

/// `hf`: BSDF sampling only (seed 000's hemispherical formulation).
pub fn hf(options: PathOptions) -> PathTracer<NoNextEvent> {
    PathTracer::new("hf", NoNextEvent, options)
}

/// `af_hf`: next-event estimation on emitters picked by `selection`, combined with BSDF
/// sampling by MIS (seed 000 §4, §5.2).
pub fn af_hf(options: PathOptions, selection: LightSelection) -> PathTracer<LightNextEvent> {
    PathTracer::new("af_hf", LightNextEvent::new(selection), options)
}

/// Renders `scene` at `width` x `height` with nobody watching (tests, scripts): prepares
/// `integrator`, renders without progress, cancellation or hooks.
pub fn render_image(
    integrator: &mut dyn Integrator,
    scene: &RenderScene,
    width: u32,
    height: u32,
    settings: &RenderSettings,
) -> Result<(Film, RenderStats), IntegratorError> {
    let mut film = Film::new(width, height);
    let stats = render(
        integrator,
        scene,
        &mut film,
        settings,
        &RenderControl::unattended(),
    )?;
    Ok((film, stats))
}
