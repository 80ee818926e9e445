//! Light paths through the portals (issue 66): paths that start at the sun and enter the
//! scene through its openings, connected to the camera at every vertex it can see (light
//! tracing, t = 1). They carry what camera paths find worst: sunlight thrown by a glossy
//! surface onto a diffuse one that the camera sees.
//!
//! The sun's lines are those through the portals: a portal is picked by its area projected
//! along the sun's direction, a point on it uniformly, and the line through it along the sun's
//! direction is traced from outside the scene, so that whatever it meets first (a pane, a
//! sill, the floor inside) is where the sunlight lands, as it would without portals. A line
//! through several portals is drawn from each of them, so a point x that the sun reaches
//! first along its line has the area density p(x) = |cos_x| * n(x) / A, with A the portals'
//! projected area and n(x) the portals the line crosses.

use crate::portal::Portal;
use fenestra_core::mis::MisHeuristic;
use fenestra_core::stats::RayCounters;
use fenestra_core::{Frame, Ray, Rgb, Sampler, Vec2, Vec3};
use fenestra_render::bsdf::Bsdf;
use fenestra_render::integrator::{
    seen_density, sides_agree, LightPaths, LightSide, PathOptions, Roulette,
};
use fenestra_render::light::{DistantLight, Light, LightContext};
use fenestra_render::sample_context::SampleContext;
use fenestra_render::splat::Splats;
use fenestra_render::RenderScene;
use fenestra_scene::{Camera, SurfaceInteraction};

/// Consecutive panes a light path passes straight through (as camera paths do).
const MAX_PANES: u32 = 16;

/// One sun's lines through the portals.
#[derive(Clone, Debug)]
pub struct SunThroughPortals {
    /// The sun's index in the scene's lights.
    light: usize,
    /// The direction sunlight travels.
    dir: Vec3,
    irradiance: Rgb,
    /// The portals the sun crosses, with their cumulative projected areas.
    portals: Vec<Portal>,
    cdf: Vec<f32>,
    /// Their projected area along `dir`, A.
    projected: f32,
    /// The scene's bounding sphere (centre, radius): the lines start outside it.
    sphere: (Vec3, f32),
}

impl SunThroughPortals {
    /// The lines of `sun` (light `light` of the scene) through `portals` into the scene of
    /// bounding sphere `sphere`, or `None` when no portal faces the sun.
    pub fn new(
        light: usize,
        sun: &DistantLight,
        portals: &[Portal],
        sphere: (Vec3, f32),
    ) -> Option<Self> {
        let dir = sun.direction();
        let mut kept = Vec::new();
        let mut cdf = Vec::new();
        let mut projected = 0.0;
        for p in portals {
            let a = p.area() * p.normal().dot(dir).abs();
            if a > 0.0 {
                projected += a;
                kept.push(p.clone());
                cdf.push(projected);
            }
        }
        (projected > 0.0).then_some(SunThroughPortals {
            light,
            dir,
            irradiance: sun.irradiance(),
            portals: kept,
            cdf,
            projected,
            sphere,
        })
    }

    /// The sun's power through the portals (luminance), for choosing between suns.
    pub fn power(&self) -> f32 {
        self.irradiance.luminance() * self.projected
    }

    /// A point of the portals, uniform in projected area (from `u_pick` and `u`).
    fn sample_point(&self, u_pick: f32, u: Vec2) -> Vec3 {
        let target = u_pick * self.projected;
        let i = self
            .cdf
            .partition_point(|&c| c <= target)
            .min(self.portals.len() - 1);
        self.portals[i].sample_area(u)
    }

    /// A point of the sun's line through `p` outside the scene, on the sun's side.
    fn line_start(&self, p: Vec3) -> Vec3 {
        let (centre, radius) = self.sphere;
        p - self.dir * (radius + (p - centre).length())
    }

    /// n(x): the portals crossed by the sun's line through `p`, on either side of it.
    pub fn crossings(&self, p: Vec3) -> u32 {
        let start = self.line_start(p);
        let crossed = self
            .portals
            .iter()
            .filter(|q| q.intersect(start, self.dir).is_some());
        crossed.count() as u32
    }

    /// The area density with which the sun's lines reach `p` (a surface point of normal
    /// `ng` that the sun reaches first along its line), p(x) = |cos_x| n(x) / A.
    pub fn density(&self, p: Vec3, ng: Vec3) -> f32 {
        ng.dot(self.dir).abs() * self.crossings(p) as f32 / self.projected
    }
}

/// The light paths of the scene's suns through the portals: a sun picked by its power
/// through them, `per_sample` paths per camera sample.
#[derive(Clone, Debug)]
pub struct SunPaths {
    suns: Vec<SunThroughPortals>,
    /// Cumulative powers of `suns`.
    cdf: Vec<f32>,
    per_sample: f32,
}

impl SunPaths {
    /// The light paths of the suns (distant lights) of `scene` through `portals`,
    /// `per_sample` of them per camera sample; `None` when no portal faces a sun.
    pub fn new(scene: &RenderScene, portals: &[Portal], per_sample: f32) -> Option<Self> {
        let sphere = scene.scene.bounding_sphere();
        let suns: Vec<_> = (scene.lights.lights.iter().enumerate())
            .filter_map(|(i, l)| match l {
                Light::Distant(sun) => SunThroughPortals::new(i, sun, portals, sphere),
                _ => None,
            })
            .collect();
        let mut total = 0.0;
        let cdf = (suns.iter())
            .map(|s| {
                total += s.power();
                total
            })
            .collect();
        (!suns.is_empty()).then_some(SunPaths {
            suns,
            cdf,
            per_sample,
        })
    }

    /// The suns' count.
    pub fn len(&self) -> usize {
        self.suns.len()
    }

    /// Whether there are none (never, as built).
    pub fn is_empty(&self) -> bool {
        self.suns.is_empty()
    }

    /// Probability of picking sun `k`.
    fn pick(&self, k: usize) -> f32 {
        let total = self.cdf.last().copied().unwrap_or(0.0);
        (self.suns[k].power() / total).max(f32::MIN_POSITIVE)
    }
}

impl LightPaths for SunPaths {
    fn emitted(&self, light: usize, p: Vec3, ng: Vec3) -> f32 {
        (self.suns.iter().enumerate())
            .find(|(_, s)| s.light == light)
            .map_or(0.0, |(k, s)| {
                self.per_sample * self.pick(k) * s.density(p, ng)
            })
    }
}

/// How light paths are weighed against a path tracer's next-event samples of the suns.
#[derive(Clone, Copy)]
pub struct Joined<'a> {
    /// The MIS heuristic.
    pub mis: MisHeuristic,
    /// The path tracer's probability of picking a light at a vertex
    /// ([`NextEvent::light_pick`](fenestra_render::integrator::NextEvent::light_pick)).
    pub light_pick: &'a (dyn Fn(&LightContext, usize) -> f32 + Sync),
}

/// Light tracing from suns through portals into a film of `width` x `height` pixels (the
/// whole image's).
pub struct LightTracer<'a> {
    pub(crate) scene: &'a RenderScene,
    pub(crate) camera: &'a Camera,
    pub(crate) suns: &'a SunPaths,
    pub(crate) options: &'a PathOptions,
    pub(crate) width: u32,
    pub(crate) height: u32,
    /// The path tracer it is joined to, if any: splats are weighted by MIS against it.
    pub(crate) joined: Option<Joined<'a>>,
}

impl LightTracer<'_> {
    /// Traces one light path from `sampler`'s stream, splatting what it brings to the pixels
    /// that see its vertices; its rays are counted in `rays` (segments as bounces,
    /// connections to the camera as shadow rays).
    /// `ctx` is the camera sample the path belongs to.
    pub fn trace(
        &self,
        ctx: &SampleContext,
        sampler: &mut Sampler,
        splats: &mut Splats,
        rays: &mut RayCounters,
    ) {
        splats.count_path();
        let paths = self.suns;
        let total = paths.cdf.last().copied().unwrap_or(0.0);
        if !(total > 0.0) {
            return;
        }
        let u_pick = sampler.next_1d() * total;
        let k = (paths.cdf.partition_point(|&c| c <= u_pick)).min(paths.suns.len() - 1);
        let (sun, pick) = (&paths.suns[k], paths.pick(k));
        let mut side = LightSide::default();
        // (k pL, the path tracer's pick of the sun) at the path's first vertex.
        let first = |si: &SurfaceInteraction, joined: &Joined| {
            let at = LightContext {
                p: si.p,
                n: si.ns,
                sample: ctx,
            };
            let pixels = (self.width * self.height) as f32;
            let emitted = paths.emitted(sun.light, si.p, si.ng) * pixels;
            (emitted, (joined.light_pick)(&at, sun.light))
        };
        let through = sun.sample_point(sampler.next_1d(), sampler.next_2d());
        let mut ray = Ray::new(sun.line_start(through), sun.dir);
        // The flux a line carries, E A / (pick n): n(x) is the same along the whole line.
        let n = sun.crossings(through).max(1);
        let mut beta = sun.irradiance * (sun.projected / (pick * n as f32));
        let initial = beta.max_component();
        let (mut vertices, mut panes) = (0u32, 0u32);
        let max_depth = self.options.max_depth;
        while let Some(hit) = self.scene.scene.intersect(&ray, f32::INFINITY) {
            rays.bounce += 1;
            let si = self.scene.scene.interaction(&ray, &hit);
            let bsdf = self.scene.bsdf_at(&si);
            let bsdf = bsdf.as_ref();
            let frame = if bsdf.needs_tangent() {
                si.shading_frame()
            } else {
                Frame::from_normal(si.ns)
            };
            // The light arrives from `wi` (towards where it came from).
            let wi = -ray.d;
            let wi_local = frame.to_local(wi);
            let pane = matches!(bsdf, Bsdf::ThinDielectric(_));
            if !pane {
                vertices += 1;
                if let Some(joined) = &self.joined {
                    side.arrive(si.p, si.ng, || first(&si, joined));
                }
                // A connection at vertex j makes a path of j + 1 segments with the camera's;
                // joined to a path tracer, the first vertex's light is its alone.
                let own = self.joined.is_none() || vertices > 1;
                if own && !bsdf.is_delta() && vertices < max_depth {
                    let at = (&si, bsdf, &frame);
                    self.connect(at, (wi, wi_local), beta, &side, splats, rays);
                }
                if vertices + 1 >= max_depth {
                    break;
                }
            }
            let uc = sampler.next_1d();
            let u = sampler.next_2d();
            let Some(bs) = bsdf.sample(wi_local, uc, u) else {
                break;
            };
            let wo = frame.to_world(bs.wi);
            if !sides_agree(self.options.sides, si.ng, wi, wi_local.z, wo, bs.wi.z) {
                break;
            }
            // Shading normals are not symmetric for light paths (Veach 1997 §5.3):
            // |wi.ns| |wo.ng| / (|wi.ng| |wo.ns|).
            let correction = (wi_local.z * wo.dot(si.ng)).abs() / (wi.dot(si.ng) * bs.wi.z).abs();
            if !correction.is_finite() {
                break;
            }
            beta *= bs.weight * (bsdf.importance_scale(wi_local, bs.wi) * correction);
            ray = Ray::new(si.spawn(wo), wo);
            let straight = pane && bs.wi.z * wi_local.z < 0.0;
            if let Some(joined) = self.joined.as_ref().filter(|_| !straight) {
                if pane {
                    side.arrive(si.p, si.ng, || first(&si, joined));
                }
                side.leave(bsdf, wi_local, bs.wi, bs.delta);
            }
            if straight {
                // Straight through a pane: no vertex, as for camera paths.
                panes += 1;
                if panes > MAX_PANES {
                    break;
                }
                continue;
            }
            panes = 0;
            if pane {
                // Reflected by the pane: a (delta) vertex.
                vertices += 1;
                if vertices + 1 >= max_depth {
                    break;
                }
            }
            if vertices + 1 >= self.options.rr_depth {
                // Russian roulette on the throughput relative to the path's start.
                let m = beta.max_component() / initial;
                let q = match self.options.roulette {
                    Roulette::Sqrt => m.sqrt(),
                    Roulette::Throughput => m,
                }
                .min(0.95);
                if !(q > 0.0) || sampler.next_1d() >= q {
                    break;
                }
                beta *= 1.0 / q;
            }
        }
    }

    /// Connects the non-delta vertex `si` (BSDF `bsdf` in `frame`; light arriving from `wi`,
    /// carrying `beta`; densities `side`) to the camera: what it brings, weighted by each
    /// pixel's filter around where it lands, and by MIS if joined to a path tracer.
    fn connect(
        &self,
        (si, bsdf, frame): (&SurfaceInteraction, &Bsdf, &Frame),
        (wi, wi_local): (Vec3, Vec3),
        beta: Rgb,
        side: &LightSide,
        splats: &mut Splats,
        rays: &mut RayCounters,
    ) {
        let Some(seen) = self.camera.project(si.p, self.width, self.height) else {
            return;
        };
        let wo = -seen.dir;
        let wo_local = frame.to_local(wo);
        if !sides_agree(self.options.sides, si.ng, wo, wo_local.z, wi, wi_local.z) {
            return;
        }
        let f = bsdf.eval(wo_local, wi_local);
        if f.is_black() {
            return;
        }
        // The camera's area density of the point, per unit of film filter density:
        // dir_pdf |cos_o| / d^2 (the geometric normal: it is a change of area), with the
        // shading-normal correction |wi.ns| / |wi.ng| for the light's arrival.
        let cos_in = wi_local.z.abs() / wi.dot(si.ng).abs();
        let g = seen_density(&seen, si.ng);
        let value = beta * f * (cos_in * g);
        if !value.is_finite() || value.is_black() {
            return;
        }
        rays.shadow += 1;
        let shadow = Ray::new(si.spawn(wo), wo);
        let tr = self
            .scene
            .transmittance(shadow, seen.distance * (1.0 - 1e-4));
        if tr.is_black() {
            return;
        }
        let value = value * tr;
        // The MIS weight for a pixel whose filter density at the point is q: r / (q g) is its
        // ratio of light tracing's density to the path tracer's (Veach eq. 10.9).
        let ratio = self
            .joined
            .map(|j| (j.mis, side.ratio_at_camera(bsdf, wo_local, wi_local)));
        let weight = |q: f32| match ratio {
            Some((mis, Some(r))) => mis.weight(r / (q * g), 1.0),
            _ => 1.0,
        };
        let filter = &self.camera.filter;
        if filter.is_pixel_box() {
            let (x, y) = (seen.film.x as u32, seen.film.y as u32);
            let value = value * weight(1.0);
            splats.add(x.min(self.width - 1), y.min(self.height - 1), value);
            return;
        }
        let r = filter.radius();
        let (x0, x1) = pixel_span(seen.film.x, r.x, self.width);
        let (y0, y1) = pixel_span(seen.film.y, r.y, self.height);
        for y in y0..y1 {
            for x in x0..x1 {
                let at = seen.film - Vec2::new(x as f32, y as f32);
                let q = filter.density(at);
                if q > 0.0 {
                    splats.add(x, y, value * (q * weight(q)));
                }
            }
        }
    }
}

/// The pixels along one axis whose filter of half-width `r` around their centres may reach
/// film position `f`: [first, end).
fn pixel_span(f: f32, r: f32, size: u32) -> (u32, u32) {
    let first = (f - r - 0.5).floor().max(0.0) as u32;
    let end = ((f + r + 0.5).ceil().max(0.0) as u32).min(size);
    (first.min(end), end)
}

/// The light paths of the suns of `scene` through `portals`, `per_sample` per camera sample,
/// or the error that `integrator` cannot render without them.
pub fn suns_through(
    scene: &RenderScene,
    portals: &crate::portal::Portals,
    integrator: &str,
    per_sample: f32,
) -> Result<SunPaths, fenestra_render::IntegratorError> {
    SunPaths::new(scene, portals.portals(), per_sample).ok_or_else(|| {
        fenestra_render::IntegratorError::Prepare(
            format!(
                "{integrator} traces light from suns (distant lights) through the portals: \
                 the scene has no sun, or no portal faces one"
            )
            .into(),
        )
    })
}
