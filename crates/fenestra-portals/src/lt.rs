//! `lt`: light tracing from the sun through the portals (issue 66's light paths, t = 1). Each
//! camera sample of the image traces one light path instead of a camera path; its vertices
//! are splatted into the pixels that see them. It renders the light of suns (distant lights)
//! that enters through the portals and reaches the camera from a non-delta surface, which is
//! the whole image of a sun-lit room without sky, mirrors or glass in direct view: the
//! light-path half of a combination with the path tracer, and its check against af_hf.

use crate::light_paths::{suns_through, LightTracer, SunThroughPortals};
use crate::lp_hf::source_settings;
use crate::portal::Portals;
use crate::source::{PortalSource, Sourced};
use crate::PortalError;
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_core::{Rgb, Sampler};
use fenestra_render::driver::{
    next_pass_size, render_passes, Budget, PassEstimator, PassInfo, PixelState,
};
use fenestra_render::film::Film;
use fenestra_render::integrator::{PathOptions, Split};
use fenestra_render::sample_context::SampleContext;
use fenestra_render::settings::RenderSettings;
use fenestra_render::splat::Splats;
use fenestra_render::{Integrator, IntegratorError, RenderControl, RenderScene};
use serde_json::json;

/// The lt integrator: light paths from the suns through the portals `source` gives.
pub struct Lt {
    options: PathOptions,
    source: PortalSource,
    portals: Portals,
    suns: Vec<SunThroughPortals>,
    /// Cumulative powers of `suns`.
    cdf: Vec<f32>,
}

impl Lt {
    /// Light tracing with `options` (path length, roulette, sides) through the portals of
    /// `source`.
    pub fn new(options: PathOptions, source: PortalSource) -> Self {
        Lt {
            options,
            source,
            portals: Portals::default(),
            suns: Vec::new(),
            cdf: Vec::new(),
        }
    }
}

impl Integrator for Lt {
    fn name(&self) -> &str {
        "lt"
    }

    fn settings(&self) -> serde_json::Value {
        json!({
            "max_depth": self.options.max_depth,
            "rr_depth": self.options.rr_depth,
            "roulette": self.options.roulette,
            "sides": self.options.sides,
            "portals": source_settings(&self.source, &self.portals),
        })
    }

    fn prepare(
        &mut self,
        scene: &RenderScene,
        control: &RenderControl,
    ) -> Result<(), IntegratorError> {
        let Sourced { portals, .. } = self.source.portals(scene, control)?;
        if portals.is_empty() {
            return Err(PortalError::NoPortals("lt").into());
        }
        self.suns = suns_through(scene, portals.portals());
        if self.suns.is_empty() {
            return Err(IntegratorError::Prepare(
                "lt traces light from suns (distant lights) through the portals: the scene \
                 has no sun, or no portal faces one"
                    .into(),
            ));
        }
        let mut total = 0.0;
        self.cdf = self
            .suns
            .iter()
            .map(|s| {
                total += s.power();
                total
            })
            .collect();
        self.portals = portals;
        Ok(())
    }

    /// Light paths splat anywhere in the image: a tile would miss its pixels' splats from
    /// other tiles' paths, and the film-state file holds no splats yet.
    fn split(&self) -> Split {
        Split::Whole
    }

    fn render(
        &self,
        scene: &RenderScene,
        film: &mut Film,
        settings: &RenderSettings,
        control: &RenderControl,
    ) -> RenderStats {
        let mut passes = LightPasses {
            lt: self,
            budget: Budget::new(settings.spp, settings.time_limit),
            size: 1,
            current: 0,
        };
        let mut stats = render_passes(&mut passes, scene, film, settings, control);
        stats.max_depth = Some(self.options.max_depth);
        stats
            .extra
            .insert("light_paths".into(), film.light_paths as f64);
        stats
    }
}

/// The pass schedule: passes of 1, 2, 4, ... up to 32 light paths per pixel, each pixel's
/// sample tracing one light path.
struct LightPasses<'a> {
    lt: &'a Lt,
    budget: Budget,
    size: u32,
    current: u32,
}

impl PassEstimator for LightPasses<'_> {
    type BlockStats = Splats;

    fn expected_samples(&self, pixels: u64) -> Option<u64> {
        self.budget.expected_samples(pixels)
    }

    fn begin_pass(&mut self, pass: &PassInfo) -> bool {
        self.current = self.budget.next_pass(pass, self.size);
        self.current > 0
    }

    fn block_stats(&self, _: u32, _: u32) -> Splats {
        Splats::default()
    }

    fn samples(&self, _: &PixelState) -> u32 {
        self.current
    }

    /// One light path from the sample's stream; the pixel itself gets nothing (its light
    /// comes as other paths' splats).
    fn sample(
        &self,
        scene: &RenderScene,
        ctx: &SampleContext,
        sampler: &mut Sampler,
        splats: &mut Splats,
        rays: &mut RayCounters,
    ) -> Rgb {
        let lt = self.lt;
        let tracer = LightTracer {
            scene,
            camera: &scene.scene.camera,
            suns: &lt.suns,
            cdf: &lt.cdf,
            options: &lt.options,
            width: ctx.width,
            height: ctx.height,
        };
        tracer.trace(sampler, splats, rays);
        Rgb::ZERO
    }

    fn take_splats(&self, splats: &mut Splats) -> Option<Splats> {
        Some(std::mem::take(splats))
    }

    fn end_pass(&mut self, _: &RenderScene, _: &Film, _: Vec<Splats>) -> bool {
        self.budget.done += self.current;
        self.size = next_pass_size(self.size);
        true
    }
}
