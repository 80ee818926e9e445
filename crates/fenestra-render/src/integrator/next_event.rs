//! Next-event strategies: how a path tracer chooses directions towards light at a shading
//! point besides BSDF sampling, and with what density it would have chosen a direction that
//! BSDF sampling took (for the MIS weight of light found that way). Strategies share the path
//! loop of [`PathTracer`](super::PathTracer) and its MIS bookkeeping.

use crate::bsdf::Bsdf;
use crate::control::RenderControl;
use crate::integrator::{Beyond, IntegratorError, LightRays, Sides};
use crate::light::{LightContext, LightHit, LightRecords};
use crate::path_sample::PathSample;
use crate::render_scene::RenderScene;
use crate::sample_context::SampleContext;
use fenestra_core::mis::MisHeuristic;
use fenestra_core::stats::RenderStats;
use fenestra_core::{Frame, Ray, Rgb, Vec3};
use fenestra_scene::SurfaceInteraction;

/// A shading point as next-event strategies see it.
#[derive(Clone, Copy)]
pub struct Shading<'a> {
    /// The surface point.
    pub si: &'a SurfaceInteraction,
    /// Its BSDF.
    pub bsdf: &'a Bsdf,
    /// Its shading frame (computed once per vertex, used by every light sample).
    pub frame: Frame,
    /// Direction towards where the path came from (world).
    pub wo: Vec3,
    /// `wo` in the shading frame.
    pub wo_local: Vec3,
    /// Which normals decide the surface's sides.
    pub sides: Sides,
    /// The sample being taken.
    pub sample: &'a SampleContext,
}

impl Shading<'_> {
    /// What a light sampler sees of this point.
    pub fn light_context(&self) -> LightContext<'_> {
        LightContext {
            p: self.si.p,
            n: self.si.ns,
            sample: self.sample,
        }
    }

    /// Whether `wi` and `wo` lie on the sides of the geometric surface that the shading
    /// frame claims (`wi_local_z`: `wi`'s local z), which guards against light leaks through
    /// shading normals; always, where the shading normal alone decides.
    pub fn sides_agree(&self, wi: Vec3, wi_local_z: f32) -> bool {
        sides_agree(
            self.sides,
            self.si.ng,
            self.wo,
            self.wo_local.z,
            wi,
            wi_local_z,
        )
    }

    /// The BSDF for light arriving from `wi` (world): the local direction and f, or `None`
    /// when the sides disagree or f vanishes.
    pub fn bsdf_toward(&self, wi: Vec3) -> Option<(Vec3, Rgb)> {
        let wi_local = self.frame.to_local(wi);
        if !self.sides_agree(wi, wi_local.z) {
            return None;
        }
        let f = self.bsdf.eval(self.wo_local, wi_local);
        (!f.is_black()).then_some((wi_local, f))
    }
}

/// Whether `wi` and `wo` lie on the sides of the geometric surface (normal `ng`) that their
/// local z (shading frame) claims; always, where the shading normal alone decides (`sides`).
pub fn sides_agree(sides: Sides, ng: Vec3, wo: Vec3, wo_z: f32, wi: Vec3, wi_z: f32) -> bool {
    sides == Sides::Shading || (wi.dot(ng) * wo.dot(ng) > 0.0) == (wi_z * wo_z > 0.0)
}

/// The vertex a BSDF-sampled ray left from, as MIS needs it when the ray finds light.
#[derive(Clone, Copy, Debug)]
pub struct Scattered<V> {
    /// The vertex's position.
    pub p: Vec3,
    /// Its shading normal.
    pub n: Vec3,
    /// The BSDF's solid-angle density of the sampled direction.
    pub bsdf_pdf: f32,
    /// What the next-event strategy kept of the vertex.
    pub vertex: V,
}

impl<V> Scattered<V> {
    /// What a light sampler saw of this vertex.
    pub fn light_context<'a>(&self, sample: &'a SampleContext) -> LightContext<'a> {
        LightContext {
            p: self.p,
            n: self.n,
            sample,
        }
    }
}

/// A light that a BSDF-sampled ray found: which light and where.
#[derive(Clone, Copy, Debug)]
pub struct Found<'a> {
    /// Index of the light in the scene's lights.
    pub light: usize,
    /// Where the ray met it.
    pub hit: LightHit<'a>,
    /// Whether the path was refracted by smooth glass on its way from the vertex (only for
    /// strategies that follow refractions, [`NextEvent::follows_refraction`]): then the
    /// direction is the one the path left the vertex along, and only samples that follow
    /// refractions (probes, not shadow rays) could have found the light.
    pub refracted: bool,
}

/// A next-event strategy of a path tracer.
pub trait NextEvent: Send + Sync {
    /// Whether the strategy samples anything (false: BSDF sampling alone, `hf`).
    const SAMPLES: bool = true;

    /// What the strategy keeps of a shading vertex: computed once there, used by its own
    /// sample and by the MIS weight of light that the next BSDF-sampled ray finds.
    type Vertex: Copy + Default;

    /// What the strategy keeps of a sample while its probe ray is traced (`()` for
    /// strategies that make none).
    type Probe: Copy;

    /// The strategy's settings (part of the integrator's).
    fn settings(&self) -> serde_json::Value;

    /// Scene-dependent state (light samplers, estimated geometry), built once before
    /// rendering.
    fn prepare(
        &mut self,
        _scene: &RenderScene,
        _control: &RenderControl,
    ) -> Result<(), IntegratorError> {
        Ok(())
    }

    /// The state kept of the non-delta vertex `s`.
    fn vertex(&self, scene: &RenderScene, s: &Shading) -> Self::Vertex;

    /// One next-event sample at `s` for the path sample `sample` (drawn from its stream):
    /// the light it finds, weighted by MIS (`mis`) against BSDF sampling and divided by its
    /// density. Samples that need a ray traced leave it in `out` (the path loop traces them,
    /// several paths' at once): a shadow ray with what the sample brings if the way is
    /// clear, or a probe ray that [`NextEvent::probed`] finishes; the return value is what
    /// samples without rays bring. Light samples that learning samplers learn from go to
    /// the sample's records, or with their shadow ray.
    fn sample(
        &self,
        scene: &RenderScene,
        s: &Shading,
        vertex: &Self::Vertex,
        mis: MisHeuristic,
        sample: &mut PathSample,
        out: &mut LightRays<Self::Probe>,
    ) -> Rgb;

    /// Finishes the sample `probe`, whose probe ray `ray` met `beyond`: what it brings,
    /// weighted and divided as [`NextEvent::sample`] says. `sample` is the path sample it
    /// belongs to.
    fn probed(
        &self,
        _scene: &RenderScene,
        _probe: &Self::Probe,
        _ray: &Ray,
        _beyond: &Beyond,
        _sample: &SampleContext,
    ) -> Rgb {
        Rgb::ZERO
    }

    /// Whether the strategy's probe rays go on through smooth glass by refraction
    /// ([`ProbeRay::refractions`](super::ProbeRay)): then a path refracted on its way from a
    /// vertex keeps that vertex for MIS, and the strategy's density of a light found so
    /// ([`Found::refracted`]) is that of the direction the path left the vertex along.
    fn follows_refraction(&self) -> bool {
        false
    }

    /// Whether the strategy learns from the render's passes at all (known before
    /// `prepare`): such a render cannot be split into pieces.
    fn learning(&self) -> bool {
        false
    }

    /// Whether the strategy learns from the light samples of pass `pass`.
    fn learns(&self, _pass: u32) -> bool {
        false
    }

    /// Learns from a pass's light samples, every block's in block order.
    fn learn(&self, _blocks: &[LightRecords]) {}

    /// Solid-angle density with which [`NextEvent::sample`] at `from` gives the direction
    /// `wi` along which a BSDF-sampled ray found `found`.
    fn pdf(
        &self,
        scene: &RenderScene,
        from: &Scattered<Self::Vertex>,
        wi: Vec3,
        found: Found,
        sample: &SampleContext,
    ) -> f32;

    /// Probability that a sample at a vertex seen as `ctx` takes the compact light `light` by
    /// a shadow ray (for the MIS weight against light paths from it); 0 where it does not.
    fn light_pick(&self, _scene: &RenderScene, _ctx: &LightContext, _light: usize) -> f32 {
        0.0
    }

    /// Adds the strategy's own figures to a render's statistics.
    fn report(&self, _stats: &mut RenderStats) {}
}

/// No next-event estimation: BSDF sampling alone (`hf`).
pub struct NoNextEvent;

impl NextEvent for NoNextEvent {
    const SAMPLES: bool = false;
    type Vertex = ();
    type Probe = ();

    fn settings(&self) -> serde_json::Value {
        serde_json::json!({})
    }

    fn vertex(&self, _: &RenderScene, _: &Shading) {}

    fn sample(
        &self,
        _: &RenderScene,
        _: &Shading,
        _: &(),
        _: MisHeuristic,
        _: &mut PathSample,
        _: &mut LightRays<()>,
    ) -> Rgb {
        Rgb::ZERO
    }

    fn pdf(&self, _: &RenderScene, _: &Scattered<()>, _: Vec3, _: Found, _: &SampleContext) -> f32 {
        0.0
    }
}
