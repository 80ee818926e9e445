//! Next-event estimation on emitters (`af_hf`): a light picked by the integrator's light
//! sampler, a point or direction on it, a shadow ray, and MIS against the BSDF (seed 000 §4,
//! §5.2).

use super::next_event::{Found, NextEvent, Scattered, Shading};
use super::{IntegratorError, LightRays, ShadowRay};
use crate::control::RenderControl;
use crate::light::{LightContext, LightRecord, LightRecords, LightSampler, LightSelection, Picks};
use crate::path_sample::PathSample;
use crate::render_scene::RenderScene;
use crate::sample_context::SampleContext;
use fenestra_core::mis::MisHeuristic;
use fenestra_core::stats::RenderStats;
use fenestra_core::{Rgb, Vec2, Vec3};

/// Builds a light sampler for a scene.
type BuildSampler = dyn Fn(&RenderScene) -> Box<dyn LightSampler> + Send + Sync;

/// Light sampling with a light sampler built when prepared: one of the fixed
/// [`LightSelection`]s or any other (learned samplers of research crates).
pub struct LightNextEvent {
    name: String,
    build: Box<BuildSampler>,
    sampler: Box<dyn LightSampler>,
    /// Whether the sampler learns from the render's passes (known before it is built).
    learning: bool,
    /// Whether an estimate may take several lights (known before it is built).
    several: bool,
    /// The fixed selection it samples by, if it is one.
    selection: Option<LightSelection>,
}

/// The light sampler before preparation: it picks nothing.
struct Unprepared;

impl LightSampler for Unprepared {
    fn sample(&self, _: &LightContext, _: f32) -> Option<(usize, f32)> {
        None
    }
    fn pmf(&self, _: &LightContext, _: usize) -> f32 {
        0.0
    }
}

impl LightNextEvent {
    /// Light sampling by `selection` (the sampler is built by `prepare`).
    pub fn new(selection: LightSelection) -> Self {
        let next_event = LightNextEvent {
            selection: Some(selection),
            ..Self::with_sampler(selection.as_str(), move |scene| selection.build(scene))
        };
        match selection {
            LightSelection::All | LightSelection::Split | LightSelection::Auto => {
                next_event.taking_several()
            }
            _ => next_event,
        }
    }

    /// Light sampling by the sampler `build` makes for the scene when prepared; `name`
    /// identifies it in the integrator's settings.
    pub fn with_sampler(
        name: impl Into<String>,
        build: impl Fn(&RenderScene) -> Box<dyn LightSampler> + Send + Sync + 'static,
    ) -> Self {
        LightNextEvent {
            name: name.into(),
            build: Box::new(build),
            sampler: Box::new(Unprepared),
            learning: false,
            several: false,
            selection: None,
        }
    }

    /// Marks the sampler as one whose estimates may take several lights
    /// ([`LightSampler::sample_all`]).
    pub fn taking_several(self) -> Self {
        LightNextEvent {
            several: true,
            ..self
        }
    }

    /// Whether an estimate may take several lights.
    pub fn takes_several(&self) -> bool {
        self.several
    }

    /// This light sampling for a strategy that draws one light at a time (a one-pick
    /// mixture): the default selection, which may split, becomes power selection, which its
    /// pilot would otherwise weigh against splitting; `None` for a sampler whose estimates
    /// take several lights by choice.
    pub fn one_at_a_time(self) -> Option<Self> {
        if self.selection == Some(LightSelection::Auto) {
            Some(Self::new(LightSelection::Power))
        } else {
            (!self.several).then_some(self)
        }
    }

    /// As [`LightNextEvent::with_sampler`], for a sampler that learns from the render's
    /// passes ([`LightSampler::learns`]): the render then cannot be split into pieces.
    pub fn with_learning_sampler(
        name: impl Into<String>,
        build: impl Fn(&RenderScene) -> Box<dyn LightSampler> + Send + Sync + 'static,
    ) -> Self {
        LightNextEvent {
            learning: true,
            ..Self::with_sampler(name, build)
        }
    }

    /// Whether the sampler learns from the render's passes.
    pub fn learning(&self) -> bool {
        self.learning
    }

    /// The light sampler.
    pub fn sampler(&self) -> &dyn LightSampler {
        self.sampler.as_ref()
    }

    /// Replaces the prepared light sampler by what `f` makes of it (a strategy that takes some
    /// lights its own way wraps it).
    pub fn replace_sampler(
        &mut self,
        f: impl FnOnce(Box<dyn LightSampler>) -> Box<dyn LightSampler>,
    ) {
        let sampler = std::mem::replace(&mut self.sampler, Box::new(Unprepared));
        self.sampler = f(sampler);
    }

    /// One light sample at `s` for the path sample `sample`, weighted by MIS against the
    /// BSDF: its shadow rays (one per light picked) go to `shadows`, each with its record if
    /// the sample's records keep this sample's.
    /// Other strategies call it for their share of light sampling.
    /// With `compact_only`, only compact lights contribute ([`crate::light::Light::is_compact`]: Dirac
    /// lights and the sun; strategies that reach the other lights by other means use it for
    /// those); the light pick probability still divides, so the estimate of the compact
    /// lights' share stays unbiased.
    pub fn sample_light(
        &self,
        scene: &RenderScene,
        s: &Shading,
        compact_only: bool,
        mis: MisHeuristic,
        sample: &mut PathSample,
        shadows: &mut Vec<ShadowRay>,
    ) {
        self.sample_light_share(scene, s, (compact_only, 1.0), mis, sample, shadows);
    }

    /// [`LightNextEvent::sample_light`] taken with probability `share` at this vertex (a
    /// strategy that picks it or another per vertex): its densities are `share` times the
    /// light sampler's, in the estimate and in the MIS weight.
    pub fn sample_light_share(
        &self,
        scene: &RenderScene,
        s: &Shading,
        (compact_only, share): (bool, f32),
        mis: MisHeuristic,
        sample: &mut PathSample,
        shadows: &mut Vec<ShadowRay>,
    ) {
        // The pick and the point on the light stratified together: the triangles of an
        // emitter are lights of their own, and an emitter's samples should cover it as a
        // 2D sample over the whole would.
        let u3 = sample.sampler.next_3d();
        let (u_pick, u) = (u3.x, Vec2::new(u3.y, u3.z));
        let mut picks = Picks::default();
        self.sampler
            .sample_all(&s.light_context(), u_pick, &mut picks);
        for &pick in picks.as_slice() {
            if let Some(shadow) = self.light_sample(
                scene,
                s,
                (pick, share, u),
                compact_only,
                mis,
                sample.records,
            ) {
                sample.rays.shadow += 1;
                shadows.push(shadow);
            }
        }
    }

    /// The shadow ray towards light `index`, picked with probability `pick` (and the light
    /// sampling taken with probability `share`), in a direction drawn with `u`, and what it
    /// brings to `s` weighted by MIS; see [`LightNextEvent::sample_light`].
    fn light_sample(
        &self,
        scene: &RenderScene,
        s: &Shading,
        ((index, pick), share, u): ((usize, f32), f32, Vec2),
        compact_only: bool,
        mis: MisHeuristic,
        records: &LightRecords,
    ) -> Option<ShadowRay> {
        let light = &scene.lights.lights[index];
        if compact_only && !light.is_compact() {
            return None;
        }
        let ctx = s.light_context();
        let ls = (self.sampler).sample_li(&scene.scene, &scene.lights, &ctx, (index, pick), u)?;
        let (wi_local, f) = s.bsdf_toward(ls.wi)?;
        let (ray, tmax) = s.si.shadow_ray(ls.wi, ls.point);
        let light_pdf = share * ls.pdf;
        let weight = if ls.delta {
            1.0
        } else {
            mis.weight(light_pdf, s.bsdf.pdf(s.wo_local, wi_local))
        };
        let record = records.on().then(|| LightRecord {
            p: s.si.p,
            n: s.si.ns,
            light: index as u32,
            wi: ls.wi,
            weight: (f * ls.li).luminance() * wi_local.z.abs() / light_pdf,
        });
        Some(ShadowRay {
            ray,
            tmax,
            value: f * ls.li * (wi_local.z.abs() * weight / light_pdf),
            light: index,
            mis: weight,
            record,
        })
    }

    /// Probability that [`LightNextEvent::sample_light`] at `ctx` takes light `light`.
    pub fn light_pick(&self, ctx: &LightContext, light: usize) -> f32 {
        self.sampler.pmf(ctx, light)
    }

    /// Density with which [`LightNextEvent::sample_light`] at `ctx` gives the direction `wi`
    /// towards `found` (the light sampler's joint density of the pick and the direction);
    /// zero for light found through refractions, which no shadow ray follows.
    pub fn light_pdf(
        &self,
        scene: &RenderScene,
        ctx: &LightContext,
        wi: Vec3,
        found: Found,
    ) -> f32 {
        if found.refracted {
            return 0.0;
        }
        (self.sampler).pdf_li(&scene.scene, &scene.lights, ctx, found.light, wi, found.hit)
    }
}

impl NextEvent for LightNextEvent {
    type Vertex = ();
    type Probe = ();

    fn settings(&self) -> serde_json::Value {
        serde_json::json!({ "light_selection": self.name })
    }

    fn prepare(
        &mut self,
        scene: &RenderScene,
        control: &RenderControl,
    ) -> Result<(), IntegratorError> {
        self.sampler = (self.build)(scene);
        if let Some((what, _)) = self.sampler.choice() {
            control.progress.note(&what);
        }
        Ok(())
    }

    fn vertex(&self, _: &RenderScene, _: &Shading) {}

    fn sample(
        &self,
        scene: &RenderScene,
        s: &Shading,
        _: &(),
        mis: MisHeuristic,
        sample: &mut PathSample,
        out: &mut LightRays<()>,
    ) -> Rgb {
        self.sample_light(scene, s, false, mis, sample, &mut out.shadows);
        Rgb::ZERO
    }

    fn light_pick(&self, _: &RenderScene, ctx: &LightContext, light: usize) -> f32 {
        self.light_pick(ctx, light)
    }

    fn report(&self, stats: &mut RenderStats) {
        if let Some((_, gain)) = self.sampler.choice() {
            stats.extra.insert("light_split_gain".into(), gain);
        }
    }

    fn learning(&self) -> bool {
        self.learning
    }

    fn learns(&self, pass: u32) -> bool {
        self.sampler.learns(pass)
    }

    fn learn(&self, blocks: &[LightRecords]) {
        self.sampler.learn(blocks);
    }

    fn pdf(
        &self,
        scene: &RenderScene,
        from: &Scattered<()>,
        wi: Vec3,
        found: Found,
        sample: &SampleContext,
    ) -> f32 {
        self.light_pdf(scene, &from.light_context(sample), wi, found)
    }
}
