//! Unidirectional path tracing with Russian roulette (seed 000 §3.2.1): one path loop for
//! every next-event strategy. At each non-delta vertex the strategy takes its sample; a
//! BSDF-sampled ray that finds an emitter or escapes to the environment is weighted by MIS
//! against the strategy's density of that direction at the vertex it left.
//!
//! A cache of indirect light (seed 003 ch. 2) plugs in as a [`Gather`]: at a vertex where
//! it answers, its estimate replaces the path's continuation, and the BSDF-sampled ray only
//! collects the emitters it finds.

use super::next_event::{Found, NextEvent, Scattered, Shading};
use super::{Integrator, IntegratorError, Split};
use crate::bsdf::Bsdf;
use crate::control::RenderControl;
use crate::driver::{render_progressive, PathEstimator, SampleContext};
use crate::film::Film;
use crate::light::{LightHit, LightRecords};
use crate::render_scene::RenderScene;
use crate::settings::RenderSettings;
use fenestra_core::mis::MisHeuristic;
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_core::{Ray, Rgb, Sampler, Vec3};
use fenestra_scene::Hit;

/// Consecutive panes a path may pass straight through (as visibility rays do).
const MAX_PANES: u32 = 16;

/// Options shared by the path tracers.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct PathOptions {
    /// Maximum path length in segments (2 = direct light only).
    pub max_depth: u32,
    /// How BSDF sampling and the next-event strategy are combined.
    pub mis: MisHeuristic,
    /// Path length from which Russian roulette may end a path.
    pub rr_depth: u32,
}

impl Default for PathOptions {
    fn default() -> Self {
        PathOptions {
            max_depth: 8,
            mis: MisHeuristic::Power { beta: 2.0 },
            rr_depth: 3,
        }
    }
}

/// A path tracer with the next-event strategy `N`.
pub struct PathTracer<N> {
    name: &'static str,
    next_event: N,
    options: PathOptions,
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
        }
    }

    /// The next-event strategy.
    pub fn next_event(&self) -> &N {
        &self.next_event
    }

    /// MIS weight of the BSDF technique for light `found` by a BSDF-sampled ray along `wi`
    /// from `from` (`None`: the camera, or a delta bounce, which no strategy samples).
    fn bsdf_weight(
        &self,
        scene: &RenderScene,
        from: Option<&Scattered<N::Vertex>>,
        wi: Vec3,
        found: Found,
        ctx: &SampleContext,
    ) -> f32 {
        match from {
            Some(from) if N::SAMPLES => self.options.mis.weight(
                from.bsdf_pdf,
                self.next_event.pdf(scene, from, wi, found, ctx),
            ),
            _ => 1.0,
        }
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
    fn li(
        &self,
        scene: &RenderScene,
        ray: Ray,
        sampler: &mut Sampler,
        ctx: &SampleContext,
        records: &mut LightRecords,
        rays: &mut RayCounters,
    ) -> Rgb {
        self.trace(
            scene,
            ray,
            Start::CAMERA,
            sampler,
            ctx,
            records,
            rays,
            &mut NoGather,
        )
    }

    fn learns(&self, pass: u32) -> bool {
        self.next_event.learns(pass)
    }

    fn learn(&self, blocks: &[LightRecords]) {
        self.next_event.learn(blocks);
    }
}

impl<N: NextEvent> PathTracer<N> {
    /// Radiance arriving at `ray`'s origin along it, from a path that starts as `start` says;
    /// `gather` may supply indirect light at the vertices it chooses; the light samples
    /// taken go to `records`.
    #[allow(clippy::too_many_arguments)]
    pub fn trace(
        &self,
        scene: &RenderScene,
        mut ray: Ray,
        start: Start,
        sampler: &mut Sampler,
        ctx: &SampleContext,
        records: &mut LightRecords,
        rays: &mut RayCounters,
        gather: &mut (impl Gather + ?Sized),
    ) -> Rgb {
        let max_depth = self.options.max_depth;
        let mut l = Rgb::ZERO;
        let mut beta = Rgb::ONE;
        // The vertex the current ray left from, for MIS (`None` at the camera and after a
        // delta bounce).
        let mut from: Option<Scattered<N::Vertex>> = None;
        // `segments` counts the path's segments up to the vertex being shaded; passing
        // straight through a thin pane adds none (visibility rays pass panes too).
        let mut segments = start.segments;
        let mut panes = 0;
        let mut first = start.segments == 0;
        let mut emitted = start.emitted;
        let mut known = start.hit;
        // Set once a gather has supplied the indirect light: the next hit only adds emission.
        let mut gathered = false;
        loop {
            segments += 1;
            if !first {
                rays.bounce += 1;
            }
            first = false;
            let hit = match known.take() {
                Some(hit) => Some(hit),
                None => scene.scene.intersect(&ray, f32::INFINITY),
            };
            let Some(hit) = hit else {
                for &e in scene.lights.environments.iter().filter(|_| emitted) {
                    let found = Found {
                        light: e,
                        hit: LightHit::Escaped,
                    };
                    let w = self.bsdf_weight(scene, from.as_ref(), ray.d, found, ctx);
                    l += beta * scene.lights.lights[e].le(LightHit::Escaped, ray.d) * w;
                }
                break;
            };
            let si = scene.scene.interaction(&ray, &hit);
            if let Some((index, le)) = scene
                .lights
                .surface_emission(&si, ray.d)
                .filter(|_| emitted)
            {
                if !le.is_black() {
                    let found = Found {
                        light: index,
                        hit: LightHit::Surface(&si),
                    };
                    l += beta * le * self.bsdf_weight(scene, from.as_ref(), ray.d, found, ctx);
                }
            }
            emitted = true;
            if gathered {
                break;
            }
            let bsdf = scene.bsdf_at(&si);
            let bsdf = bsdf.as_ref();
            let pane = matches!(bsdf, Bsdf::ThinDielectric(_));
            // At the last vertex only a pane's straight-through part may continue the path.
            let at_limit = segments >= max_depth;
            if at_limit && !pane {
                break;
            }
            let frame = si.shading_frame();
            let wo = -ray.d;
            let shading = Shading {
                si: &si,
                bsdf,
                frame,
                wo,
                wo_local: frame.to_local(wo),
                sample: ctx,
            };
            let vertex = if bsdf.is_delta() {
                N::Vertex::default()
            } else {
                self.next_event.vertex(scene, &shading)
            };
            if N::SAMPLES && !bsdf.is_delta() {
                l += beta
                    * self.next_event.sample(
                        scene,
                        &shading,
                        &vertex,
                        self.options.mis,
                        sampler,
                        records,
                        rays,
                    );
            }
            if !bsdf.is_delta() {
                if let Some(indirect) = gather.indirect(scene, &shading, segments, rays) {
                    l += beta * indirect;
                    gathered = true;
                }
            }
            let uc = sampler.next_1d();
            let u = sampler.next_2d();
            let Some(bs) = bsdf.sample(shading.wo_local, uc, u) else {
                break;
            };
            let wi = frame.to_world(bs.wi);
            if !shading.sides_agree(wi, bs.wi.z) {
                break;
            }
            beta *= bs.weight;
            if pane && bs.wi.z * shading.wo_local.z < 0.0 {
                // Straight through a pane: the same line, so MIS keeps the previous vertex.
                panes += 1;
                if panes > MAX_PANES {
                    break;
                }
                segments -= 1;
                ray = Ray::new(si.spawn(wi), wi);
                continue;
            }
            if at_limit {
                break;
            }
            panes = 0;
            from = (!bs.delta).then_some(Scattered {
                p: si.p,
                n: si.ns,
                bsdf_pdf: bs.pdf,
                vertex,
            });
            if segments + 1 >= self.options.rr_depth {
                // Russian roulette (seed 000 §3.2.1): continue with probability q, divide by q.
                let q = beta.max_component().min(0.95);
                if q <= 0.0 || sampler.next_1d() >= q {
                    break;
                }
                beta *= 1.0 / q;
            }
            ray = Ray::new(si.spawn(wi), wi);
        }
        l
    }
}
