//! Light paths through the portals (issue 66): paths that start at the sun and enter the
//! scene through its openings, connected to the camera at every vertex it can see (light
//! tracing, t = 1). They carry what camera paths find worst: sunlight thrown by a glossy
//! surface onto a diffuse one that the camera sees.
//!
//! The sun's lines are those through the portals: a direction is drawn from the sun (one
//! for a distant light, uniform in the cone of the sky's sun disk), a portal is picked by
//! its area projected along it, a point on it uniformly, and the line through it along the sun's
//! direction is traced from outside the scene, so that whatever it meets first (a pane, a
//! sill, the floor inside) is where the sunlight lands, as it would without portals. A line
//! through several portals is drawn from each of them, so a point x that the sun reaches
//! first along its line has the area density p(x) = |cos_x| * n(x) / A, with A the portals'
//! projected area and n(x) the portals the line crosses, both along the line's direction.
//! With a learned emission ([`crate::emission`]) the points are drawn from a mixture of that
//! and a histogram over each portal, and p(x) sums the histogram's density over the portals
//! the line crosses in the same way.

use crate::emission::{Emission, Tally, UNIFORM_SHARE};
use crate::portal::Portal;
use fenestra_core::mis::MisHeuristic;
use fenestra_core::stats::RayCounters;
use fenestra_core::{Frame, Ray, Rgb, Sampler, Vec2, Vec3};
use fenestra_render::bsdf::Bsdf;
use fenestra_render::integrator::{
    seen_density, sides_agree, FirstVertex, LightPaths, LightSide, PathOptions, Roulette,
};
use fenestra_render::light::{Light, LightContext, SunDisk};
use fenestra_render::sample_context::SampleContext;
use fenestra_render::splat::Splats;
use fenestra_render::RenderScene;
use fenestra_scene::{Camera, SurfaceInteraction};

/// Consecutive panes a light path passes straight through (as camera paths do).
const MAX_PANES: u32 = 16;

/// The camera rays (a grid over the image, per axis) whose first hits measure
/// [`SunPaths::sunlight_through_portals`].
const SEEN_GRID: (u32, u32) = (48, 27);

/// Where a sun's light comes from.
#[derive(Clone, Copy, Debug)]
enum SunShape {
    /// One direction (a distant light): the direction its light travels, its irradiance.
    Direction(Vec3, Rgb),
    /// A disk at infinity (the sky's sun).
    Disk(SunDisk),
}

impl SunShape {
    /// The direction the light of a line travels (from `u`: uniform over a disk's cone) and
    /// the irradiance per unit of its direction's density (a Dirac direction's counts 1).
    fn sample(&self, u: Vec2) -> (Vec3, Rgb) {
        match self {
            SunShape::Direction(dir, irradiance) => (*dir, *irradiance),
            SunShape::Disk(disk) => (-disk.sample(u), disk.radiance() * disk.solid_angle()),
        }
    }

    /// The density of [`SunShape::sample`]'s direction towards it being `towards`, as
    /// [`Light::pdf_at_infinity`] gives it.
    fn pdf(&self, towards: Vec3) -> f32 {
        match self {
            SunShape::Direction(..) => 1.0,
            SunShape::Disk(disk) => disk.pdf(towards),
        }
    }

    /// Whether BSDF-sampled rays can find it.
    fn found(&self) -> bool {
        matches!(self, SunShape::Disk(_))
    }

    /// The direction its light travels along the axis, and the irradiance it brings there.
    fn axis(&self) -> (Vec3, Rgb) {
        match self {
            SunShape::Direction(dir, irradiance) => (*dir, *irradiance),
            SunShape::Disk(disk) => (-disk.axis(), disk.radiance() * disk.solid_angle()),
        }
    }
}

/// One sun's lines through the portals.
#[derive(Clone, Debug)]
pub struct SunThroughPortals {
    /// The sun's index in the scene's lights.
    light: usize,
    shape: SunShape,
    /// The portals the sun crosses.
    portals: Vec<Portal>,
    /// The scene's bounding sphere (centre, radius): the lines start outside it.
    sphere: (Vec3, f32),
    /// The learned density over the portals, if learned.
    emission: Option<Emission>,
}

/// Where a light path's line crossed the portal it was drawn on.
#[derive(Clone, Copy, Debug)]
pub struct LineStart {
    /// The sun's index among the suns through the portals.
    pub sun: usize,
    /// The portal's index among the sun's.
    pub portal: usize,
    /// The point of the portal's unit square.
    pub unit: Vec2,
}

impl SunThroughPortals {
    /// The lines of the sun light `light` of `scene` through `portals` into the scene of
    /// bounding sphere `sphere`, or `None` when that light is no sun or no portal faces it.
    fn new(
        scene: &RenderScene,
        light: usize,
        portals: &[Portal],
        sphere: (Vec3, f32),
    ) -> Option<Self> {
        let shape = match &scene.lights.lights[light] {
            Light::Distant(sun) => SunShape::Direction(sun.direction(), sun.irradiance()),
            Light::Environment(e) => SunShape::Disk(*e.sun()?),
            _ => return None,
        };
        let axis = shape.axis().0;
        let portals: Vec<_> = (portals.iter())
            .filter(|p| p.area() * p.normal().dot(axis).abs() > 0.0)
            .cloned()
            .collect();
        let sun = SunThroughPortals {
            light,
            shape,
            portals,
            sphere,
            emission: None,
        };
        (sun.projected(axis) > 0.0).then_some(sun)
    }

    /// The sun's power through the portals (luminance), for choosing between suns.
    pub fn power(&self) -> f32 {
        let (dir, irradiance) = self.shape.axis();
        irradiance.luminance() * self.projected(dir)
    }

    /// The portals' area projected along `dir`, A.
    fn projected(&self, dir: Vec3) -> f32 {
        (self.portals.iter())
            .map(|p| p.area() * p.normal().dot(dir).abs())
            .sum()
    }

    /// A point of the portals from `u_pick` and `u`: uniform in their area projected along
    /// `dir` (`projected` of it), or with a learned emission from its mixture with that;
    /// the portal and the point of its unit square it was drawn at.
    fn sample_point(&self, dir: Vec3, projected: f32, u_pick: f32, u: Vec2) -> (usize, Vec2) {
        let mut left = match &self.emission {
            Some(learned) if u_pick >= UNIFORM_SHARE => {
                return learned.sample((u_pick - UNIFORM_SHARE) / (1.0 - UNIFORM_SHARE), u);
            }
            Some(_) => u_pick / UNIFORM_SHARE * projected,
            None => u_pick * projected,
        };
        let last = self.portals.len() - 1;
        for (i, p) in self.portals.iter().enumerate() {
            let a = p.area() * p.normal().dot(dir).abs();
            if left < a || i == last {
                return (i, u);
            }
            left -= a;
        }
        unreachable!("a sun through portals has some")
    }

    /// The density per unit area across the line along `dir` through `p` with which
    /// [`SunThroughPortals::sample_point`] draws it (`projected`, A, along `dir`): n / A for
    /// the n portals it crosses, mixed with the learned density's over them.
    fn line_density(&self, p: Vec3, dir: Vec3, projected: f32) -> f32 {
        let start = self.line_start(p, dir);
        let (mut crossed, mut learned) = (0u32, 0.0f32);
        for (i, q) in self.portals.iter().enumerate() {
            let Some(t) = q.intersect(start, dir) else {
                continue;
            };
            crossed += 1;
            if let Some(emission) = &self.emission {
                let across = q.area() * q.normal().dot(dir).abs();
                learned += emission.density(i, q.unit_of(start + dir * t)) / across;
            }
        }
        let uniform = crossed as f32 / projected;
        match self.emission {
            Some(_) => UNIFORM_SHARE * uniform + (1.0 - UNIFORM_SHARE) * learned,
            None => uniform,
        }
    }

    /// A point of the line along `dir` through `p` outside the scene, on the sun's side.
    fn line_start(&self, p: Vec3, dir: Vec3) -> Vec3 {
        let (centre, radius) = self.sphere;
        p - dir * (radius + (p - centre).length())
    }

    /// n(x): the portals crossed by the line along `dir` through `p`, on either side of it.
    pub fn crossings(&self, p: Vec3, dir: Vec3) -> u32 {
        let start = self.line_start(p, dir);
        let crossed = (self.portals.iter()).filter(|q| q.intersect(start, dir).is_some());
        crossed.count() as u32
    }

    /// The area density with which the lines along `dir` reach `p` (a surface point of
    /// normal `ng` that the sun reaches first along its line), p(x) = |cos_x| n(x) / A
    /// uniformly.
    pub fn density(&self, p: Vec3, ng: Vec3, dir: Vec3) -> f32 {
        let projected = self.projected(dir);
        if !(projected > 0.0) {
            return 0.0;
        }
        ng.dot(dir).abs() * self.line_density(p, dir, projected)
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
    /// The light paths of the suns (distant lights and the sky's sun) of `scene` through
    /// `portals`, `per_sample` of them per camera sample; `None` when no portal faces a sun.
    pub fn new(scene: &RenderScene, portals: &[Portal], per_sample: f32) -> Option<Self> {
        let sphere = scene.scene.bounding_sphere();
        let suns: Vec<_> = (0..scene.lights.lights.len())
            .filter_map(|i| SunThroughPortals::new(scene, i, portals, sphere))
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

    /// The share of the sunlight on the surfaces the camera sees (the first hits of a grid
    /// of its rays; each sun's irradiance along its axis through thin glass, times the
    /// cosine on the side the camera sees) that arrives along lines through the portals: all
    /// of the direct sunlight there that light paths can bring, and a sign of how much of the
    /// rest they can. `None` where the camera sees no sunlit surface.
    pub fn sunlight_through_portals(&self, scene: &RenderScene) -> Option<f64> {
        let camera = &scene.scene.camera;
        let (w, h) = SEEN_GRID;
        let (mut through, mut all) = (0.0f64, 0.0f64);
        for y in 0..h {
            for x in 0..w {
                let ray = camera.generate_ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), w, h);
                let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
                    continue;
                };
                let si = scene.scene.interaction(&ray, &hit);
                for sun in &self.suns {
                    let (dir, irradiance) = sun.shape.axis();
                    let cos = -si.ng.dot(dir) * si.ng.dot(-ray.d).signum();
                    if !(cos > 0.0) {
                        continue;
                    }
                    let shadow = Ray::new(si.spawn(-dir), -dir);
                    let tr = scene.transmittance(shadow, f32::INFINITY);
                    let lit = f64::from((irradiance * tr).luminance() * cos);
                    all += lit;
                    if sun.crossings(si.p, dir) > 0 {
                        through += lit;
                    }
                }
            }
        }
        (all > 0.0).then(|| through / all)
    }

    /// Empty sums of light per cell of each sun's portals, for a pilot.
    pub fn tally(&self) -> Tally {
        Tally::new(self.suns.iter().map(|s| &s.portals[..]))
    }

    /// These light paths, started from the emission `tally` learned (suns whose pilot
    /// paths brought nothing keep the uniform density).
    pub fn learned(&self, tally: &Tally) -> SunPaths {
        let mut learned = self.clone();
        for (sun, emission) in learned.suns.iter_mut().zip(tally.emissions()) {
            sun.emission = emission;
        }
        learned
    }

    /// Probability of picking sun `k`.
    fn pick(&self, k: usize) -> f32 {
        let total = self.cdf.last().copied().unwrap_or(0.0);
        (self.suns[k].power() / total).max(f32::MIN_POSITIVE)
    }
}

impl SunPaths {
    /// [`LightPaths::emitted`] for sun `k`.
    fn emitted_by(&self, k: usize, p: Vec3, ng: Vec3, towards: Vec3) -> f32 {
        let sun = &self.suns[k];
        let direction = sun.shape.pdf(towards);
        if !(direction > 0.0) {
            return 0.0;
        }
        self.per_sample * self.pick(k) * direction * sun.density(p, ng, -towards)
    }
}

impl LightPaths for SunPaths {
    fn emitted(&self, light: usize, p: Vec3, ng: Vec3, towards: Vec3) -> f32 {
        (self.suns.iter().position(|s| s.light == light))
            .map_or(0.0, |k| self.emitted_by(k, p, ng, towards))
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
    /// connections to the camera as shadow rays). `ctx` is the camera sample the path
    /// belongs to. Returns where it started, if it did.
    pub fn trace(
        &self,
        ctx: &SampleContext,
        sampler: &mut Sampler,
        splats: &mut Splats,
        rays: &mut RayCounters,
    ) -> Option<LineStart> {
        splats.count_path();
        let paths = self.suns;
        let total = paths.cdf.last().copied().unwrap_or(0.0);
        if !(total > 0.0) {
            return None;
        }
        let u_pick = sampler.next_1d() * total;
        let k = (paths.cdf.partition_point(|&c| c <= u_pick)).min(paths.suns.len() - 1);
        let (sun, pick) = (&paths.suns[k], paths.pick(k));
        let (dir, irradiance) = sun.shape.sample(sampler.next_2d());
        let projected = sun.projected(dir);
        if !(projected > 0.0) {
            return None;
        }
        let mis = self.joined.map_or(MisHeuristic::Balance, |j| j.mis);
        let mut side = LightSide::new(mis);
        // What the densities need of the path's first vertex.
        let first = |si: &SurfaceInteraction, joined: &Joined| {
            let at = LightContext {
                p: si.p,
                n: si.ns,
                sample: ctx,
            };
            let pixels = (self.width * self.height) as f32;
            FirstVertex {
                emitted: paths.emitted_by(k, si.p, si.ng, -dir) * pixels,
                next_event: (joined.light_pick)(&at, sun.light) * sun.shape.pdf(-dir),
                found: sun.shape.found(),
            }
        };
        let (portal, unit) = sun.sample_point(dir, projected, sampler.next_1d(), sampler.next_2d());
        let through = sun.portals[portal].sample_area(unit);
        let start = LineStart {
            sun: k,
            portal,
            unit,
        };
        let mut ray = Ray::new(sun.line_start(through, dir), dir);
        // The flux a line carries, E / (pick p), p its density across the line (n / A when
        // uniform): the same along the whole line.
        let across = sun.line_density(through, dir, projected);
        if !(across > 0.0) {
            return Some(start);
        }
        let mut beta = irradiance / (pick * across);
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
        Some(start)
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
        // What a splat s of weight w and density ratio r adds to the second moment of the
        // camera paths' light that MIS shares with light paths (Splats::handed_moment).
        let per_pass = f64::from(self.suns.per_sample) * f64::from(self.width * self.height);
        let mut splat = |x: u32, y: u32, q: f32| {
            let w = weight(q);
            let s = value * (q * w);
            if let (Some((_, Some(r))), true) = (ratio, w > 0.0) {
                let squares = f64::from(s.r * s.r + s.g * s.g + s.b * s.b) / 3.0;
                let ratio = f64::from(r / (q * g));
                splats.handed_moment += squares * f64::from((2.0 - w) / w) * ratio / per_pass;
            }
            splats.add(x, y, s);
        };
        let filter = &self.camera.filter;
        if filter.is_pixel_box() {
            let (x, y) = (seen.film.x as u32, seen.film.y as u32);
            splat(x.min(self.width - 1), y.min(self.height - 1), 1.0);
            return;
        }
        let r = filter.radius();
        let (x0, x1) = pixel_span(seen.film.x, r.x, self.width);
        let (y0, y1) = pixel_span(seen.film.y, r.y, self.height);
        for y in y0..y1 {
            for x in x0..x1 {
                let q = filter.density(seen.film - Vec2::new(x as f32, y as f32));
                if q > 0.0 {
                    splat(x, y, q);
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
                "{integrator} traces light from suns (distant lights, the sky's sun) through the portals: \
                 the scene has no sun, or no portal faces one"
            )
            .into(),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Rng;

    /// Two windows one behind the other, partly overlapping along the sun's lines, their
    /// emission learned from a made-up pilot.
    fn two_windows(learned: bool) -> SunThroughPortals {
        let portals = vec![
            Portal::quad([
                Vec3::ZERO,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(2.0, 0.0, 1.5),
                Vec3::new(0.0, 0.0, 1.5),
            ]),
            Portal::Quad {
                corner: Vec3::new(1.0, 0.8, 0.5),
                e1: Vec3::new(2.0, 0.0, 0.0),
                e2: Vec3::new(0.0, 0.0, 1.0),
            },
        ];
        let mut tally = Tally::new([&portals[..]].into_iter());
        tally.add(0, 0, Vec2::new(0.1, 0.2), 5.0);
        tally.add(0, 0, Vec2::new(0.7, 0.7), 1.0);
        tally.add(0, 1, Vec2::new(0.5, 0.45), 3.0);
        let dir = Vec3::new(0.3, 1.0, -0.2).normalize();
        SunThroughPortals {
            light: 0,
            shape: SunShape::Direction(dir, Rgb::ONE),
            portals,
            sphere: (Vec3::new(1.0, 0.4, 0.75), 5.0),
            emission: learned.then(|| tally.emissions()[0].clone().expect("learned")),
        }
    }

    /// The lines [`SunThroughPortals::sample_point`] draws, binned across them, follow
    /// [`SunThroughPortals::line_density`] (chi-square), uniform or learned, and that density
    /// integrates to one: the flux a light path carries is divided by the density it was
    /// drawn with.
    #[test]
    fn lines_follow_their_density() {
        for learned in [false, true] {
            let sun = two_windows(learned);
            let (dir, _) = sun.shape.axis();
            let projected = sun.projected(dir);
            let across = Frame::from_normal(dir);
            let on_plane = |p: Vec3| Vec2::new(p.dot(across.s), p.dot(across.t));
            // The bins: a grid over the portals' shadows on the plane across the lines.
            let corners: Vec<Vec2> = (sun.portals.iter())
                .flat_map(|p| {
                    let Portal::Quad { corner, e1, e2 } = *p else {
                        unreachable!()
                    };
                    [corner, corner + e1, corner + e2, corner + e1 + e2].map(on_plane)
                })
                .collect();
            let lo = corners.iter().fold(Vec2::MAX, |a, &b| a.min(b)) - 0.01;
            let hi = corners.iter().fold(Vec2::MIN, |a, &b| a.max(b)) + 0.01;
            let (bins, sub, n) = (16usize, 64usize, 200_000u32);
            let cell = (hi - lo) / bins as f32;
            let mut expected = vec![0.0f64; bins * bins];
            for (b, e) in expected.iter_mut().enumerate() {
                for k in 0..sub * sub {
                    let at = lo
                        + cell
                            * (Vec2::new((b % bins) as f32, (b / bins) as f32)
                                + (Vec2::new((k % sub) as f32, (k / sub) as f32) + 0.5)
                                    / sub as f32);
                    let p = across.s * at.x + across.t * at.y;
                    *e += f64::from(sun.line_density(p, dir, projected));
                }
                *e *= f64::from(cell.x * cell.y) / (sub * sub) as f64 * f64::from(n);
            }
            let total: f64 = expected.iter().sum();
            assert!((total / f64::from(n) - 1.0).abs() < 0.005, "{total}");
            let mut observed = vec![0.0f64; bins * bins];
            let mut rng = Rng::new(7);
            for _ in 0..n {
                let (portal, unit) =
                    sun.sample_point(dir, projected, rng.next_f32(), rng.next_2d());
                let at = (on_plane(sun.portals[portal].sample_area(unit)) - lo) / cell;
                let (x, y) = (at.x as usize, at.y as usize);
                observed[y.min(bins - 1) * bins + x.min(bins - 1)] += 1.0;
            }
            let fit = fenestra_eval::chi2::chi2(&observed, &expected, 3.0).expect("bins");
            assert!(fit.p_value > 1e-3, "learned {learned}: {fit:?}");
        }
    }
}
