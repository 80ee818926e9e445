//! `lt`: light tracing from the sun through the portals (issue 66's light paths, t = 1). Each
//! camera sample of the image traces one light path instead of a camera path; its vertices
//! are splatted into the pixels that see them. It renders the light of suns (distant lights)
//! that enters through the portals and reaches the camera from a non-delta surface, which is
//! the whole image of a sun-lit room without sky, mirrors or glass in direct view: the
//! light-path half of a combination with the path tracer, and its check against af_hf.

use crate::light_passes::LightPasses;
use crate::light_paths::{suns_through, SunPaths};
use crate::lp_hf::source_settings;
use crate::portal::Portals;
use crate::source::{PortalSource, Sourced};
use crate::PortalError;
use fenestra_core::stats::RenderStats;
use fenestra_render::film::Film;
use fenestra_render::integrator::{PathOptions, Split};
use fenestra_render::settings::RenderSettings;
use fenestra_render::{Integrator, IntegratorError, RenderControl, RenderScene};
use serde_json::json;

/// The lt integrator: light paths from the suns through the portals `source` gives.
pub struct Lt {
    options: PathOptions,
    source: PortalSource,
    portals: Portals,
    /// The suns' light paths (set when prepared).
    suns: Option<SunPaths>,
}

impl Lt {
    /// Light tracing with `options` (path length, roulette, sides) through the portals of
    /// `source`.
    pub fn new(options: PathOptions, source: PortalSource) -> Self {
        Lt {
            options,
            source,
            portals: Portals::default(),
            suns: None,
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
        self.suns = Some(suns_through(scene, &portals, "lt", 1.0)?);
        self.portals = portals;
        Ok(())
    }

    /// Light paths splat anywhere in the image, so a tile would miss what other tiles' light
    /// paths bring to its pixels; sample ranges merge (each sample's light paths are its own,
    /// and the film-state file keeps their splats).
    fn split(&self) -> Split {
        Split::Samples
    }

    fn render(
        &self,
        scene: &RenderScene,
        film: &mut Film,
        settings: &RenderSettings,
        control: &RenderControl,
    ) -> RenderStats {
        let suns = self.suns.as_ref().expect("lt renders once prepared");
        LightPasses::new(None, suns, &self.options, 1.0).render(scene, film, settings, control)
    }
}
