//! The densities with which two strategies make the same path, for the MIS weight that joins
//! light paths (started at a light, connected to the camera: t = 1) to the path tracer's
//! next-event samples of that light (issue 66; Veach 1997 §10.2). A path x0 (the camera), x1,
//! ..., xn, lit at xn straight from a light, is made
//! - by the path tracer with density P(xn) p->(x1) ... p->(xn): BSDF sampling from the camera
//!   (p->(x1) the camera's), then the next-event strategy's pick P of the light at xn;
//! - by light tracing with density k pL(xn) p<-(xn-1) ... p<-(x1): xn where the light paths
//!   reach it, BSDF sampling towards the camera, then the connection of x1 to the camera;
//!   k = L / N for L light paths and N samples of each pixel (k light paths per camera
//!   sample times the image's pixels);
//!
//! all in area measure, except that the light's end of a path lit from infinity is a
//! direction (solid angle; a Dirac direction counts 1). Where BSDF sampling can find the
//! light too (the sky's sun is a disk), the path tracer has two strategies for the last
//! segment, P(xn) and the BSDF's density of the direction (1 after a delta lobe), and the
//! light side stands them together by [`MisHeuristic::combined`], so that the three weights
//! sum to one. A path lit at the camera's first vertex (n = 1) is the path tracer's
//! alone: its pixel sample and its light sample are each drawn in proportion to what they
//! integrate there, which the densities do not see (the light paths' count in a pixel is
//! the noise they add), and on a 32x32 sunlit room light paths that took their share of the
//! sunlit floor had 5x its variance per sample. Each side keeps the ratio of the other side's densities to its own
//! along its path, r = p_light / p_camera at the end. The combination is unbiased whatever r
//! is, as long as both sides compute the very same r for the same path, so:
//! - densities come from [`Bsdf::mis_pdf`], with the camera side's direction first at the
//!   camera side's sampling, the light side's first at the light side's;
//! - the density of a vertex sampled from a delta lobe counts as 1 on both sides (a specular
//!   vertex's delta factors cancel, as in pbrt-v4's BDPT);
//! - the probabilities of the choices at thin panes and Russian roulette count on neither.

use crate::bsdf::Bsdf;
use crate::sample_context::SampleContext;
use fenestra_core::mis::MisHeuristic;
use fenestra_core::{Vec2, Vec3};
use fenestra_scene::{Camera, Projection};

/// Light paths that share some lights' light with a path tracer's next-event samples.
pub trait LightPaths: Send + Sync {
    /// The light paths per camera sample times the density with which they reach the
    /// surface point `p` (geometric normal `ng`) straight from light `light` along the unit
    /// direction `towards` it (k pL(x) once multiplied by the image's pixels): the light's
    /// density of the direction (solid angle; a Dirac direction counts 1) times the area
    /// density of `p` along it; 0 where they do not start at that light or cannot reach `p`
    /// from it.
    fn emitted(&self, light: usize, p: Vec3, ng: Vec3, towards: Vec3) -> f32;
}

/// What the light side needs of the path tracer at a light path's first vertex y1 = xn.
#[derive(Clone, Copy, Debug)]
pub struct FirstVertex {
    /// k pL(y1) ([`LightPaths::emitted`] times the image's pixels).
    pub emitted: f32,
    /// The path tracer's next-event density of the light's direction at y1: its pick of
    /// the light times the light's density of the direction (a Dirac direction counts 1).
    pub next_event: f32,
    /// Whether the path tracer's BSDF-sampled rays can find the light (a disk such as the
    /// sky's sun, not a direction).
    pub found: bool,
}

/// The area density at `to` (geometric normal `ng`) of a direction drawn at `from` with
/// solid-angle density `pdf`: pdf |cos_to| / d^2.
pub fn to_area(pdf: f32, from: Vec3, to: Vec3, ng: Vec3) -> f32 {
    let d = to - from;
    let d2 = d.length_squared();
    pdf * ng.dot(d).abs() / (d2 * d2.sqrt())
}

/// The camera's area density of the point of geometric normal `ng` it sees as `seen`, per
/// unit of the film position's density: dir_pdf |cos| / d^2.
pub fn seen_density(seen: &Projection, ng: Vec3) -> f32 {
    seen.dir_pdf * seen.dir.dot(ng).abs() / (seen.distance * seen.distance)
}

/// The density with which a camera sample of the pixel at `(x, y)` reaches the point `p`
/// (geometric normal `ng`) first: the pixel filter's density where `p` lands times
/// [`seen_density`]; 0 where it lands outside the film or the filter.
pub fn pixel_density(camera: &Camera, p: Vec3, ng: Vec3, ctx: &SampleContext) -> f32 {
    let Some(seen) = camera.project(p, ctx.width, ctx.height) else {
        return 0.0;
    };
    let at = seen.film - Vec2::new(ctx.x as f32, ctx.y as f32);
    camera.filter.density(at) * seen_density(&seen, ng)
}

/// A path vertex as the densities need it.
#[derive(Clone, Copy, Debug)]
struct Point {
    p: Vec3,
    ng: Vec3,
}

/// The path tracer's side: r = p_light / p_camera so far, up to the last vertex.
#[derive(Clone, Copy, Debug, Default)]
pub struct CameraSide {
    /// p<-(x1) ... p<-(x(i-2)) / (p->(x1) ... p->(xi)) at vertex xi; 0 once light tracing
    /// cannot make the path (x1 outside the film, or left by a delta lobe).
    ratio: f32,
    /// x(i-1) and xi.
    prev: Option<Point>,
    here: Option<Point>,
    /// The solid-angle density with which the path left xi (`None`: a delta lobe).
    fwd: Option<f32>,
}

impl CameraSide {
    /// The path reaches its next vertex, `p` of geometric normal `ng`; `pixel` gives the
    /// camera's density of it if it is the first ([`pixel_density`]).
    pub fn arrive(&mut self, p: Vec3, ng: Vec3, pixel: impl FnOnce() -> f32) {
        match self.here {
            None => {
                let pc = pixel();
                self.ratio = if pc > 0.0 { 1.0 / pc } else { 0.0 };
            }
            Some(here) => {
                if let Some(fwd) = self.fwd {
                    self.ratio /= to_area(fwd, here.p, p, ng);
                }
            }
        }
        self.prev = self.here;
        self.here = Some(Point { p, ng });
    }

    /// The path leaves its vertex (BSDF `bsdf`) from `wo` (towards the camera's side) along
    /// `wi`, both local, sampled from a delta lobe or not.
    pub fn leave(&mut self, bsdf: &Bsdf, wo: Vec3, wi: Vec3, delta: bool) {
        let Some(here) = self.here else { return };
        match self.prev {
            None if delta => self.ratio = 0.0,
            Some(prev) if !delta => {
                self.ratio *= to_area(bsdf.mis_pdf(wi, wo), here.p, prev.p, prev.ng);
            }
            _ => {}
        }
        if !self.ratio.is_finite() {
            self.ratio = 0.0;
        }
        self.fwd = (!delta).then(|| bsdf.mis_pdf(wo, wi));
    }

    /// r for the path closed at the current vertex (BSDF `bsdf`, `wo` towards the camera's
    /// side) by a next-event sample towards a light along `wl` (local) that the light paths
    /// reach it from with `emitted` ([`LightPaths::emitted`]), taken with the density
    /// `next_event` ([`FirstVertex::next_event`]): 0 where light tracing cannot make the path
    /// (or does not: n = 1), infinite where only it can.
    pub fn ratio_to_light(
        &self,
        bsdf: &Bsdf,
        wo: Vec3,
        wl: Vec3,
        emitted: f32,
        next_event: f32,
    ) -> f32 {
        let (Some(here), Some(prev)) = (self.here, self.prev) else {
            return 0.0;
        };
        if !(self.ratio > 0.0 && emitted > 0.0) {
            return 0.0;
        }
        let rev = to_area(bsdf.mis_pdf(wl, wo), here.p, prev.p, prev.ng);
        finite_or_zero(emitted * self.ratio * rev / next_event)
    }

    /// r for the path whose current vertex was left (after [`CameraSide::leave`]) along a
    /// direction that found a light at infinity, which the light paths reach the vertex
    /// (position, geometric normal) from with `emitted` ([`LightPaths::emitted`]): the BSDF's
    /// density of the direction is the path tracer's (1 after a delta lobe).
    pub fn ratio_found(&self, emitted: impl FnOnce(Vec3, Vec3) -> f32) -> f32 {
        let (Some(here), Some(_)) = (self.here, self.prev) else {
            return 0.0;
        };
        if !(self.ratio > 0.0) {
            return 0.0;
        }
        let emitted = emitted(here.p, here.ng);
        if !(emitted > 0.0) {
            return 0.0;
        }
        finite_or_zero(emitted * self.ratio / self.fwd.unwrap_or(1.0))
    }
}

/// `r`, or 0 where it is 0/0 (a density that vanishes on both sides).
fn finite_or_zero(r: f32) -> f32 {
    if r.is_nan() {
        0.0
    } else {
        r
    }
}

/// The light path's side: p_light and p_camera so far, up to the last vertex.
#[derive(Clone, Copy, Debug)]
pub struct LightSide {
    /// How the path tracer's two strategies for the light's direction stand together.
    mis: MisHeuristic,
    /// k pL(y1) p<-(y2) ... p<-(yk) at vertex yk (y1 = xn).
    light: f32,
    /// P(y1) p->(y1) ... p->(y(k-2)), the path tracer's densities of the vertices beyond the
    /// last two (its density of y(k-1) depends on where the camera is); P(y1) stands for its
    /// next-event sample and its BSDF sampling together once y1 is left.
    camera: f32,
    /// Whether BSDF sampling can find the light ([`FirstVertex::found`]).
    found: bool,
    /// Whether the path tracer can make the path: not where its densities of the light's
    /// direction vanish (a delta lobe at y1, whose next-event sample evaluates the BSDF's
    /// other lobes, and a light that BSDF sampling cannot find).
    possible: bool,
    prev: Option<Point>,
    here: Option<Point>,
    /// The solid-angle density with which the light path left yk (`None`: a delta lobe).
    rev: Option<f32>,
}

impl LightSide {
    /// A light path about to start, weighed by the heuristic `mis`.
    pub fn new(mis: MisHeuristic) -> Self {
        LightSide {
            mis,
            light: 0.0,
            camera: 0.0,
            found: false,
            possible: false,
            prev: None,
            here: None,
            rev: None,
        }
    }

    /// The light path reaches its next vertex, `p` of geometric normal `ng`; `first` gives
    /// what the densities need there if it is the first.
    pub fn arrive(&mut self, p: Vec3, ng: Vec3, first: impl FnOnce() -> FirstVertex) {
        match self.here {
            None => {
                let first = first();
                self.light = first.emitted;
                self.camera = first.next_event;
                self.found = first.found;
                self.possible = first.emitted > 0.0 && first.next_event > 0.0;
            }
            Some(here) => {
                if let Some(rev) = self.rev {
                    self.light *= to_area(rev, here.p, p, ng);
                }
            }
        }
        self.prev = self.here;
        self.here = Some(Point { p, ng });
    }

    /// The light path leaves its vertex (BSDF `bsdf`) from `wi` (towards the light's side)
    /// along `wo` (towards the camera's), both local, sampled from a delta lobe or not.
    pub fn leave(&mut self, bsdf: &Bsdf, wi: Vec3, wo: Vec3, delta: bool) {
        let Some(here) = self.here else { return };
        match self.prev {
            None => {
                // The path tracer's densities of the light's direction at y1: its next-event
                // sample's (none at a delta lobe) and, where it can find the light, its BSDF
                // sampling's.
                let next_event = if delta { 0.0 } else { self.camera };
                let bsdf_found = match (self.found, delta) {
                    (false, _) => 0.0,
                    (true, true) => 1.0,
                    (true, false) => bsdf.mis_pdf(wo, wi),
                };
                self.camera = self.mis.combined(next_event, bsdf_found);
                self.possible = self.light > 0.0 && self.camera > 0.0;
            }
            Some(prev) if !delta => {
                self.camera *= to_area(bsdf.mis_pdf(wo, wi), here.p, prev.p, prev.ng);
            }
            _ => {}
        }
        self.rev = (!delta).then(|| bsdf.mis_pdf(wi, wo));
    }

    /// r without the camera's density of the current vertex (BSDF `bsdf`, `wi` towards the
    /// light's side) for the path closed by its connection to the camera along `wc` (local):
    /// divided by a pixel's [`pixel_density`] it is that pixel's r; `None` where the path
    /// tracer cannot make the path, 0 at the first vertex (n = 1: the path tracer's alone).
    pub fn ratio_at_camera(&self, bsdf: &Bsdf, wc: Vec3, wi: Vec3) -> Option<f32> {
        let here = self.here?;
        if !self.possible {
            return None;
        }
        let Some(prev) = self.prev else {
            return Some(0.0);
        };
        let fwd = to_area(bsdf.mis_pdf(wc, wi), here.p, prev.p, prev.ng);
        // 0/0 as the camera side takes it: the path tracer's alone.
        let r = self.light / (self.camera * fwd);
        Some(if r.is_nan() { 0.0 } else { r })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::{Phong, Ward};
    use fenestra_core::{Frame, Rgb};

    /// A path of `n` vertices in front of a camera at the origin, lit from `sun`, with
    /// glossy BSDFs whose densities are not symmetric in their directions (Phong about the
    /// mirror direction of `wo`, anisotropic Ward), each normal near the bisector of the
    /// directions to the vertex's neighbours.
    fn path(n: usize, seed: u32, sun: Vec3) -> Vec<(Vec3, Vec3, Bsdf)> {
        let mut h = fenestra_core::rng::Rng::new(u64::from(seed));
        let mut u = || h.next_f32() - 0.5;
        let p: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new(u() * 4.0, u() * 4.0, 3.0 + i as f32 + u()))
            .collect();
        (0..n)
            .map(|i| {
                let before = if i == 0 { Vec3::ZERO } else { p[i - 1] };
                let after = if i + 1 == n { p[i] + sun } else { p[i + 1] };
                let bisector = (before - p[i]).normalize() + (after - p[i]).normalize();
                let ng = (bisector + Vec3::new(u(), u(), u()) * 0.6).normalize();
                let bsdf = if i % 2 == 0 {
                    Bsdf::Phong(Phong::new(Rgb::splat(0.3), Rgb::splat(0.5), 8.0))
                } else {
                    Bsdf::Ward(Ward::new(Rgb::splat(0.2), Rgb::splat(0.6), 0.1, 0.4))
                };
                (p[i], ng, bsdf)
            })
            .collect()
    }

    type Path = [(Vec3, Vec3, Bsdf)];

    /// Vertex i's (1-based; 0 is the camera at the origin) position.
    fn point(x: &Path, i: usize) -> Vec3 {
        if i == 0 {
            Vec3::ZERO
        } else {
            x[i - 1].0
        }
    }

    /// The direction from vertex i (1-based) towards `to`, in its local frame.
    fn local(x: &Path, i: usize, to: Vec3) -> Vec3 {
        let (p, ng, _) = &x[i - 1];
        Frame::from_normal(*ng).to_local((to - *p).normalize())
    }

    /// The camera side walked to the last vertex of `x` (seen with density `pixel`), every
    /// vertex before it left towards the next, vertex `delta` by a delta lobe.
    fn camera_walk(x: &Path, pixel: f32, delta: Option<usize>) -> CameraSide {
        let n = x.len();
        let mut c = CameraSide::default();
        for i in 1..=n {
            c.arrive(x[i - 1].0, x[i - 1].1, || pixel);
            if i < n {
                let (wo, wi) = (local(x, i, point(x, i - 1)), local(x, i, point(x, i + 1)));
                c.leave(&x[i - 1].2, wo, wi, delta == Some(i));
            }
        }
        c
    }

    /// The light side walked from the last vertex of `x` (lit from `sun`, `first` there) to
    /// the first, vertex `delta` left by a delta lobe: the first vertex's r for its pixel.
    fn light_walk(
        x: &Path,
        sun: Vec3,
        (mis, first, pixel): (MisHeuristic, FirstVertex, f32),
        delta: Option<usize>,
    ) -> Option<f32> {
        let n = x.len();
        let towards_sun = point(x, n) + sun;
        let mut l = LightSide::new(mis);
        for i in (1..=n).rev() {
            l.arrive(x[i - 1].0, x[i - 1].1, || first);
            if i > 1 {
                let light = if i == n { towards_sun } else { point(x, i + 1) };
                let (wi, wo) = (local(x, i, light), local(x, i, point(x, i - 1)));
                l.leave(&x[i - 1].2, wi, wo, delta == Some(i));
            }
        }
        let light = if n == 1 { towards_sun } else { point(x, 2) };
        let (wc, wi) = (local(x, 1, Vec3::ZERO), local(x, 1, light));
        Some(l.ratio_at_camera(&x[0].2, wc, wi)? / pixel)
    }

    /// Both sides' r for the path `x` lit from `sun` (the direction towards it), with the
    /// vertex `delta` (if any) scattering by a delta lobe.
    fn ratios(x: &Path, sun: Vec3, delta: Option<usize>) -> (f32, f32) {
        let (emitted, pick, pixel) = (0.7, 0.4, 53.0);
        let n = x.len();
        let c = camera_walk(x, pixel, delta);
        let (wo, wl) = (local(x, n, point(x, n - 1)), local(x, n, point(x, n) + sun));
        let r_camera = c.ratio_to_light(&x[n - 1].2, wo, wl, emitted, pick);
        let first = FirstVertex {
            emitted,
            next_event: pick,
            found: false,
        };
        let mis = MisHeuristic::Power { beta: 2.0 };
        let r_light = light_walk(x, sun, (mis, first, pixel), delta).expect("possible");
        (r_camera, r_light)
    }

    #[test]
    fn both_sides_compute_the_same_ratio_for_the_same_path() {
        let sun = Vec3::new(0.3, 0.8, -0.5).normalize();
        let mut compared = 0;
        for n in 2..=7 {
            for seed in 0..20 {
                let x = path(n, seed * 31 + n as u32, sun);
                for delta in std::iter::once(None).chain((2..n).map(Some)) {
                    let (c, l) = ratios(&x, sun, delta);
                    if !(c > 0.0 && c.is_finite()) {
                        // A direction below a surface: both sides' densities vanish.
                        assert!(l == c || !(l > 0.0 && l.is_finite()), "n {n}: {c} {l}");
                        continue;
                    }
                    compared += 1;
                    assert!(
                        ((c / l) - 1.0).abs() < 1e-4,
                        "n {n} seed {seed} delta {delta:?}: camera side {c}, light side {l}"
                    );
                }
            }
        }
        assert!(compared > 300, "{compared} paths compared");
        // The camera's first vertex lit directly is the path tracer's alone.
        assert_eq!(ratios(&path(1, 3, sun), sun, None), (0.0, 0.0));
    }

    /// The weights of the three strategies for the path `x` lit from a disk towards `sun`
    /// (next-event sample, BSDF sampling, light tracing), with the last vertex scattering by
    /// a delta lobe or not; `None` where the path tracer cannot make the path.
    fn three_weights(x: &Path, sun: Vec3, delta: bool) -> Option<[f32; 3]> {
        let mis = MisHeuristic::Power { beta: 2.0 };
        let (emitted, pick, pixel) = (7.0, 0.8, 53.0);
        let n = x.len();
        let mut c = camera_walk(x, pixel, None);
        let bsdf = &x[n - 1].2;
        let (wo, wl) = (local(x, n, point(x, n - 1)), local(x, n, point(x, n) + sun));
        let (next_event, found) = if delta {
            (0.0, 1.0)
        } else {
            let w = mis.weight(pick, bsdf.pdf(wo, wl));
            let r = c.ratio_to_light(bsdf, wo, wl, emitted, pick);
            (w * mis.with_third(w, r), 1.0 - w)
        };
        c.leave(bsdf, wo, wl, delta);
        let r = c.ratio_found(|_, _| emitted);
        if r == 0.0 {
            // A direction below a surface: the path tracer cannot make the path.
            return None;
        }
        let found = found * mis.with_third(found, r);
        let first = FirstVertex {
            emitted,
            next_event: pick,
            found: true,
        };
        let delta = delta.then_some(n);
        let r = light_walk(x, sun, (mis, first, pixel), delta).expect("possible");
        Some([next_event, found, mis.weight(r, 1.0)])
    }

    #[test]
    fn three_strategies_for_a_light_that_bsdf_sampling_finds_weigh_one_in_all() {
        let sun = Vec3::new(0.3, 0.8, -0.5).normalize();
        let mut shared = 0;
        for n in 2..=6 {
            for seed in 0..40 {
                let x = path(n, seed * 17 + n as u32, sun);
                for delta in [false, true] {
                    let Some(w) = three_weights(&x, sun, delta) else {
                        continue;
                    };
                    let sum: f32 = w.iter().sum();
                    assert!((sum - 1.0).abs() < 1e-4, "n {n} seed {seed}: {w:?}");
                    shared += usize::from(w.iter().filter(|&&w| w > 1e-3).count() > 1);
                }
            }
        }
        assert!(shared > 60, "{shared} paths shared by strategies");
    }

    #[test]
    fn light_tracing_cannot_make_a_path_whose_first_vertex_is_left_by_a_delta_lobe() {
        let x = path(3, 9, Vec3::Z);
        let mut c = CameraSide::default();
        c.arrive(x[0].0, x[0].1, || 10.0);
        c.leave(&x[0].2, Vec3::Z, Vec3::Z, true);
        c.arrive(x[1].0, x[1].1, || 10.0);
        assert_eq!(c.ratio_to_light(&x[1].2, Vec3::Z, Vec3::Z, 1.0, 1.0), 0.0);
    }
}
