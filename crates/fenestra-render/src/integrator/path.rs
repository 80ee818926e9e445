//! Unidirectional path tracing with Russian roulette (seed 000 §3.2.1): one path loop for
//! every next-event strategy. At each non-delta vertex the strategy takes its sample; a
//! BSDF-sampled ray that finds an emitter or escapes to the environment is weighted by MIS
//! against the strategy's density of that direction at the vertex it left.
//!
//! A cache of indirect light (seed 003 ch. 2) plugs in as a [`Gather`]: at a vertex where
//! it answers, its estimate replaces the path's continuation, and the BSDF-sampled ray only
//! collects the emitters it finds.

use super::light_rays::{trace_probes, trace_shadows, LightRays, ShadowRay, MAX_REFRACTIONS};
use super::next_event::{Found, NextEvent, Scattered, Shading};
use super::path_densities::{pixel_density, CameraSide, LightPaths};
use super::path_options::{PathOptions, Roulette};
use super::{Integrator, IntegratorError, Split};
use crate::bsdf::Bsdf;
use crate::control::RenderControl;
use crate::driver::{render_progressive, PathEstimator};
use crate::features::Feature;
use crate::film::Film;
use crate::light::{LightHit, LightRecords};
use crate::path_sample::{PathSample, Wave};
use crate::render_scene::RenderScene;
use crate::sample_context::SampleContext;
use crate::settings::RenderSettings;
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_core::{Frame, Ray, Rgb, Vec3};
use fenestra_scene::{Hit, PACKET};
use std::sync::Arc;

/// Consecutive panes a path may pass straight through (as visibility rays do).
const MAX_PANES: u32 = 16;

/// A path tracer with the next-event strategy `N`.
pub struct PathTracer<N> {
    name: &'static str,
    next_event: N,
    options: PathOptions,
    /// Light paths that share the light of some lights: the next-event samples of those
    /// lights are weighted by MIS against them.
    light_paths: Option<Arc<dyn LightPaths>>,
}

/// Indirect light that a cache supplies at a path vertex instead of the path's continuation.
pub trait Gather {
    /// Light reflected at `s` towards `s.wo` that arrives from other surfaces (not from
    /// emitters: the next-event strategy and the BSDF-sampled ray's emitter hits count that),
    /// or `None` to let the path go on. `segments`: the path's segments up to `s`.
    fn indirect(
        &mut self,
        scene: &RenderScene,
        s: &Shading,
        segments: u32,
        rays: &mut RayCounters,
    ) -> Option<Rgb>;
}

/// No cache: paths always go on.
pub struct NoGather;

impl Gather for NoGather {
    fn indirect(
        &mut self,
        _: &RenderScene,
        _: &Shading,
        _: u32,
        _: &mut RayCounters,
    ) -> Option<Rgb> {
        None
    }
}

/// Where a traced ray starts.
#[derive(Clone, Copy, Debug)]
pub struct Start {
    /// Path segments before the ray's origin (0: the camera).
    pub segments: u32,
    /// Whether light emitted at the ray's first hit (or from the environment, if it escapes)
    /// counts: false for rays that gather only reflected light.
    pub emitted: bool,
    /// The ray's first hit, if the caller has found it already.
    pub hit: Option<Hit>,
}

impl Start {
    /// A camera ray.
    pub const CAMERA: Start = Start {
        segments: 0,
        emitted: true,
        hit: None,
    };
}

impl<N: NextEvent> PathTracer<N> {
    /// The path tracer called `name` with the strategy `next_event`.
    pub fn new(name: &'static str, next_event: N, options: PathOptions) -> Self {
        PathTracer {
            name,
            next_event,
            options,
            light_paths: None,
        }
    }

    /// Weighs the next-event samples of the lights `light_paths` start at by MIS against
    /// them (the path tracer's part of a combination with light tracing); `None` parts the
    /// path tracer from them again.
    pub fn join_light_paths(&mut self, light_paths: Option<Arc<dyn LightPaths>>) {
        self.light_paths = light_paths;
    }

    /// The path options.
    pub fn options(&self) -> &PathOptions {
        &self.options
    }

    /// The next-event strategy.
    pub fn next_event(&self) -> &N {
        &self.next_event
    }

    /// MIS weight of the BSDF technique for light `found` by the path's current ray `ray`
    /// (`path.from`: the vertex it left, `None` at the camera or after a delta bounce, which
    /// no strategy samples; after refractions the strategy follows, the direction is the
    /// one the path left that vertex along).
    fn bsdf_weight(
        &self,
        scene: &RenderScene,
        path: &PathState<N::Vertex>,
        ray: &Ray,
        found: Found,
        ctx: &SampleContext,
    ) -> f32 {
        match &path.from {
            Some(from) if N::SAMPLES => {
                let refracted = path.refractions > 0;
                let wi = if refracted { path.from_wi } else { ray.d };
                let found = Found { refracted, ..found };
                self.options.mis.weight(
                    from.bsdf_pdf,
                    self.next_event.pdf(scene, from, wi, found, ctx),
                )
            }
            _ => 1.0,
        }
    }

    /// What multiplies the MIS weight of the next-event sample `shadow` taken at `s` once
    /// the light paths `joined` weigh in (1 for lights they do not start at).
    fn light_path_weight(
        &self,
        scene: &RenderScene,
        s: &Shading,
        path: &PathState<N::Vertex>,
        shadow: &ShadowRay,
        joined: &dyn LightPaths,
    ) -> f32 {
        let pixels = (s.sample.width * s.sample.height) as f32;
        let towards = shadow.ray.d;
        let emitted = joined.emitted(shadow.light, s.si.p, s.si.ng, towards) * pixels;
        if !(emitted > 0.0) {
            return 1.0;
        }
        let light = &scene.lights.lights[shadow.light];
        let pick = (self.next_event).light_pick(scene, &s.light_context(), shadow.light);
        let next_event = pick * light.pdf_at_infinity(towards);
        let wl = s.frame.to_local(towards);
        let r = (path.densities).ratio_to_light(s.bsdf, s.wo_local, wl, emitted, next_event);
        self.options.mis.with_third(shadow.mis, r)
    }

    /// What multiplies the MIS weight `w` of light from the environment `light` that the
    /// path's BSDF-sampled ray `ray` found once the light paths `joined` weigh in.
    fn found_light_path_weight(
        &self,
        path: &PathState<N::Vertex>,
        ray: &Ray,
        (light, w): (usize, f32),
        joined: &dyn LightPaths,
        ctx: &SampleContext,
    ) -> f32 {
        let pixels = (ctx.width * ctx.height) as f32;
        let emitted = |p, ng| joined.emitted(light, p, ng, ray.d) * pixels;
        let r = path.densities.ratio_found(emitted);
        self.options.mis.with_third(w, r)
    }

    /// Smooth-glass interfaces a probe from a vertex `segments` into the path may pass: a
    /// refraction is a vertex, and the light beyond must lie within the path's length.
    fn refractions_left(&self, segments: u32) -> u32 {
        self.options
            .max_depth
            .saturating_sub(segments + 1)
            .min(MAX_REFRACTIONS)
    }
}

impl<N: NextEvent> Integrator for PathTracer<N> {
    fn name(&self) -> &str {
        self.name
    }

    fn settings(&self) -> serde_json::Value {
        let mut s = serde_json::json!({
            "max_depth": self.options.max_depth,
            "mis": self.options.mis,
            "rr_depth": self.options.rr_depth,
            "sides": self.options.sides,
        });
        if let (Some(all), serde_json::Value::Object(own)) =
            (s.as_object_mut(), self.next_event.settings())
        {
            all.extend(own);
        }
        s
    }

    fn prepare(
        &mut self,
        scene: &RenderScene,
        control: &RenderControl,
    ) -> Result<(), IntegratorError> {
        self.next_event.prepare(scene, control)
    }

    fn split(&self) -> Split {
        // A learned light sampler learns from every pixel's samples of the early passes: a
        // piece of the render would learn something else.
        if self.next_event.learning() {
            Split::Whole
        } else {
            Split::SamplesOrTiles
        }
    }

    fn render(
        &self,
        scene: &RenderScene,
        film: &mut Film,
        settings: &RenderSettings,
        control: &RenderControl,
    ) -> RenderStats {
        let mut stats = render_progressive(self, scene, film, settings, control);
        stats.max_depth = Some(self.options.max_depth);
        self.next_event.report(&mut stats);
        stats
    }
}

impl<N: NextEvent> PathEstimator for PathTracer<N> {
    fn li(&self, scene: &RenderScene, ray: Ray, sample: &mut PathSample) -> Rgb {
        self.trace(scene, ray, Start::CAMERA, sample, &mut NoGather)
    }

    fn li_many(&self, scene: &RenderScene, wave: &mut Wave, out: &mut [Rgb]) {
        self.trace_wave(scene, wave, &mut NoGather, out);
    }

    fn learns(&self, pass: u32) -> bool {
        self.next_event.learns(pass)
    }

    fn learn(&self, blocks: &[LightRecords]) {
        self.next_event.learn(blocks);
    }
}

/// A path between two of its vertices: the ray to trace next and what the path has gathered.
pub(crate) struct PathState<V> {
    /// The ray leaving the last vertex.
    pub ray: Ray,
    /// Radiance gathered so far.
    pub l: Rgb,
    beta: Rgb,
    /// The vertex the current ray left from, for MIS (`None` at the camera and after a
    /// delta bounce but a refraction the strategy follows).
    from: Option<Scattered<V>>,
    /// The direction the path left `from` along.
    from_wi: Vec3,
    /// Smooth-glass refractions since `from` (kept for MIS when the strategy follows them).
    refractions: u32,
    /// The path's segments up to the vertex being shaded; passing straight through a thin
    /// pane adds none (visibility rays pass panes too).
    segments: u32,
    panes: u32,
    /// Whether the current ray is the path's first (not counted as a bounce).
    first: bool,
    /// Whether light emitted where the current ray ends counts.
    emitted: bool,
    /// Set once a gather has supplied the indirect light: the next hit only adds emission.
    gathered: bool,
    /// The densities of light paths' making the path, when they share its light.
    densities: CameraSide,
    /// Whether the path's denoising feature is asked for and still to be read (it has met
    /// only delta vertices since the camera): at the next non-delta vertex or where it
    /// escapes.
    feature_pending: bool,
    /// The path's denoising feature, once read.
    feature: Option<Feature>,
}

impl<V> PathState<V> {
    /// A path about to trace `ray`, which starts as `start` says.
    pub fn new(ray: Ray, start: &Start) -> Self {
        PathState {
            ray,
            l: Rgb::ZERO,
            beta: Rgb::ONE,
            from: None,
            from_wi: Vec3::ZERO,
            refractions: 0,
            segments: start.segments,
            panes: 0,
            first: start.segments == 0,
            emitted: start.emitted,
            gathered: false,
            densities: CameraSide::default(),
            feature_pending: false,
            feature: None,
        }
    }

    /// Takes `feature` as the path's denoising feature.
    fn read_feature(&mut self, feature: Feature) {
        self.feature = Some(feature);
        self.feature_pending = false;
    }
}

impl<N: NextEvent> PathTracer<N> {
    /// Radiance arriving at `ray`'s origin along it, from a path of `sample` that starts as
    /// `start` says; `gather` may supply indirect light at the vertices it chooses.
    pub fn trace(
        &self,
        scene: &RenderScene,
        ray: Ray,
        start: Start,
        sample: &mut PathSample,
        gather: &mut (impl Gather + ?Sized),
    ) -> Rgb {
        let mut path = PathState::new(ray, &start);
        let mut known = start.hit;
        let mut out = LightRays::default();
        loop {
            let hit = match known.take() {
                Some(hit) => Some(hit),
                None => scene.scene.intersect(&path.ray, f32::INFINITY),
            };
            let go_on = self.step(scene, &mut path, hit, sample, gather, &mut out);
            for shadow in out.shadows.drain(..) {
                path.l += shadow.trace(scene, sample.records);
            }
            for probe in out.probes.drain(..) {
                let beyond = probe.trace(scene, self.options.sides);
                path.l += probe.beta
                    * self
                        .next_event
                        .probed(scene, &probe.probe, &probe.ray, &beyond, sample.ctx);
            }
            if !go_on {
                break;
            }
        }
        path.l
    }

    /// The paths of `wave` traced together: each round takes the live paths eight at a time, finds their
    /// next hits by one packet query, prefetches the hits' mesh data together and takes
    /// each path one vertex further; then it traces the shadow and probe rays of all their
    /// next-event samples, eight to a packet again. Each path's radiance goes to `out`: the
    /// estimate [`PathTracer::trace`] makes of one path, whatever the other paths of the
    /// wave are (a ray's answer does not depend on its packet's other rays), so images stay
    /// the same for any thread count and for any split of a render. `gather` may supply
    /// indirect light as in [`PathTracer::trace`]; it is asked at the paths' vertices in
    /// path order round by round, so at their first hits in the order one-at-a-time tracing
    /// asks it there.
    pub fn trace_wave(
        &self,
        scene: &RenderScene,
        wave: &mut Wave,
        gather: &mut (impl Gather + ?Sized),
        out: &mut [Rgb],
    ) {
        let features = !wave.features.is_empty();
        let mut paths: Vec<PathState<N::Vertex>> = wave
            .cameras
            .iter()
            .map(|&ray| PathState {
                feature_pending: features,
                ..PathState::new(ray, &Start::CAMERA)
            })
            .collect();
        let mut live: Vec<usize> = (0..paths.len()).collect();
        let mut queued = LightRays::default();
        // The path each shadow and probe ray belongs to.
        let (mut shadow_owners, mut probe_owners) = (Vec::new(), Vec::new());
        let mut next_live = Vec::with_capacity(live.len());
        while !live.is_empty() {
            for chunk in live.chunks(PACKET) {
                let last = chunk.len() - 1;
                let packet = std::array::from_fn(|k| paths[chunk[k.min(last)]].ray);
                let found = scene.scene.intersect8(&packet, [f32::INFINITY; PACKET]);
                scene.scene.prefetch_hits(&found[..chunk.len()]);
                for (&i, hit) in chunk.iter().zip(found) {
                    wave.records.start_sample(&wave.ctxs[i]);
                    let sample = &mut wave.sample(i);
                    let go_on = self.step(scene, &mut paths[i], hit, sample, gather, &mut queued);
                    shadow_owners.resize(queued.shadows.len(), i);
                    probe_owners.resize(queued.probes.len(), i);
                    if go_on {
                        next_live.push(i);
                    }
                }
            }
            std::mem::swap(&mut live, &mut next_live);
            next_live.clear();
            trace_shadows(scene, &queued.shadows, wave.records, |k, l| {
                paths[shadow_owners[k]].l += l;
            });
            trace_probes(scene, &queued.probes, self.options.sides, |k, beyond| {
                let (i, probe) = (probe_owners[k], &queued.probes[k]);
                paths[i].l += probe.beta
                    * self.next_event.probed(
                        scene,
                        &probe.probe,
                        &probe.ray,
                        &beyond,
                        &wave.ctxs[i],
                    );
            });
            queued.shadows.clear();
            queued.probes.clear();
            shadow_owners.clear();
            probe_owners.clear();
        }
        for (o, p) in out.iter_mut().zip(&paths) {
            *o = p.l;
        }
        for (f, p) in wave.features.iter_mut().zip(&paths) {
            *f = p.feature;
        }
    }

    /// Takes the path one vertex further: `hit` is where its current ray ended. Returns
    /// whether the path goes on (with its next ray in `path.ray`).
    pub(crate) fn step(
        &self,
        scene: &RenderScene,
        path: &mut PathState<N::Vertex>,
        hit: Option<Hit>,
        sample: &mut PathSample,
        gather: &mut (impl Gather + ?Sized),
        out: &mut LightRays<N::Probe>,
    ) -> bool {
        let (ctx, rays) = (sample.ctx, &mut *sample.rays);
        let ray = path.ray;
        path.segments += 1;
        if !path.first {
            rays.bounce += 1;
        }
        path.first = false;
        let Some(hit) = hit else {
            if path.feature_pending {
                path.read_feature(Feature::escaped(scene, path.beta, ray.d));
            }
            for &e in scene.lights.environments.iter().filter(|_| path.emitted) {
                let found = Found {
                    light: e,
                    hit: LightHit::Escaped,
                    refracted: false,
                };
                let le = scene.lights.lights[e].le(LightHit::Escaped, ray.d);
                if le.is_black() {
                    continue;
                }
                let mut w = self.bsdf_weight(scene, path, &ray, found, ctx);
                if let Some(joined) = self.light_paths.as_deref() {
                    w *= self.found_light_path_weight(path, &ray, (e, w), joined, ctx);
                }
                path.l += path.beta * le * w;
            }
            return false;
        };
        let si = scene.scene.interaction(&ray, &hit);
        let emission = scene.lights.surface_emission(&si, ray.d);
        if let Some((index, le)) = emission.filter(|_| path.emitted) {
            if !le.is_black() {
                let found = Found {
                    light: index,
                    hit: LightHit::Surface(&si),
                    refracted: false,
                };
                path.l += path.beta * le * self.bsdf_weight(scene, path, &ray, found, ctx);
            }
        }
        path.emitted = true;
        if path.gathered {
            return false;
        }
        let bsdf = scene.bsdf_at(&si);
        let bsdf = bsdf.as_ref();
        let pane = matches!(bsdf, Bsdf::ThinDielectric(_));
        // At the last vertex only a pane's straight-through part may continue the path.
        let at_limit = path.segments >= self.options.max_depth;
        if at_limit && !pane {
            return false;
        }
        // Any frame around the normal serves an isotropic BSDF, and this one is the cheapest.
        let frame = if bsdf.needs_tangent() {
            si.shading_frame()
        } else {
            Frame::from_normal(si.ns)
        };
        let wo = -ray.d;
        let shading = Shading {
            si: &si,
            bsdf,
            frame,
            wo,
            wo_local: frame.to_local(wo),
            sides: self.options.sides,
            sample: ctx,
        };
        let joined = self.light_paths.as_deref();
        if joined.is_some() && !pane {
            let camera = &scene.scene.camera;
            path.densities
                .arrive(si.p, si.ng, || pixel_density(camera, si.p, si.ng, ctx));
        }
        let vertex = if bsdf.is_delta() {
            N::Vertex::default()
        } else {
            self.next_event.vertex(scene, &shading)
        };
        if N::SAMPLES && !bsdf.is_delta() {
            let (shadows, probes) = (out.shadows.len(), out.probes.len());
            path.l += path.beta
                * self
                    .next_event
                    .sample(scene, &shading, &vertex, self.options.mis, sample, out);
            for shadow in &mut out.shadows[shadows..] {
                shadow.value *= path.beta;
                if let Some(joined) = joined {
                    shadow.value *= self.light_path_weight(scene, &shading, path, shadow, joined);
                }
            }
            let refractions = self.refractions_left(path.segments);
            for probe in &mut out.probes[probes..] {
                probe.beta = path.beta;
                probe.refractions = probe.refractions.min(refractions);
            }
        }
        if !bsdf.is_delta() {
            if let Some(indirect) = gather.indirect(scene, &shading, path.segments, sample.rays) {
                path.l += path.beta * indirect;
                path.gathered = true;
            }
        }
        let uc = sample.sampler.next_1d();
        let u = sample.sampler.next_2d();
        let sampled = bsdf.sample(shading.wo_local, uc, u);
        if path.feature_pending && !bsdf.is_delta() {
            let emitted = emission.map_or(Rgb::ZERO, |(_, le)| le);
            let albedo = sampled.map(|bs| bs.weight);
            let feature = Feature::at_surface(path.beta, albedo, emitted, si.ns, ray.d);
            path.read_feature(feature);
        }
        let Some(bs) = sampled else {
            return false;
        };
        let wi = frame.to_world(bs.wi);
        if !shading.sides_agree(wi, bs.wi.z) {
            return false;
        }
        path.beta *= bs.weight;
        let straight = pane && bs.wi.z * shading.wo_local.z < 0.0;
        if joined.is_some() && !straight {
            if pane {
                path.densities.arrive(si.p, si.ng, || 0.0);
            }
            (path.densities).leave(bsdf, shading.wo_local, bs.wi, bs.delta);
        }
        if straight {
            // Straight through a pane: the same line, so MIS keeps the previous vertex.
            path.panes += 1;
            if path.panes > MAX_PANES {
                return false;
            }
            path.segments -= 1;
            path.ray = Ray::new(si.spawn(wi), wi);
            return true;
        }
        if at_limit {
            return false;
        }
        path.panes = 0;
        // Through smooth glass by refraction, as the strategy's probes go on: the vertex
        // before the glass stays the one MIS weighs light found beyond against.
        let follows = self.next_event.follows_refraction()
            && path.from.is_some()
            && path.refractions < MAX_REFRACTIONS
            && emission.is_none()
            && matches!(bsdf, Bsdf::SmoothDielectric(_))
            && bs.wi.z * shading.wo_local.z < 0.0;
        if follows {
            path.refractions += 1;
        } else if bs.delta {
            path.from = None;
        } else {
            path.from = Some(Scattered {
                p: si.p,
                n: si.ns,
                bsdf_pdf: bs.pdf,
                vertex,
            });
            path.from_wi = wi;
            path.refractions = 0;
        }
        if path.segments + 1 >= self.options.rr_depth {
            // Russian roulette (seed 000 §3.2.1): continue with probability q, divide by q.
            let m = path.beta.max_component();
            let q = match self.options.roulette {
                Roulette::Sqrt => m.sqrt(),
                Roulette::Throughput => m,
            }
            .min(0.95);
            if q <= 0.0 || sample.sampler.next_1d() >= q {
                return false;
            }
            path.beta *= 1.0 / q;
        }
        path.ray = Ray::new(si.spawn(wi), wi);
        true
    }
}
