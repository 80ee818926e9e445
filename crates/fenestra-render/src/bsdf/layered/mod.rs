//! pbrt-v4's coated materials as pbrt-v4 renders them: a dielectric coat over a base
//! (Lambertian, or a conductor) with a slab of optical thickness between them, evaluated,
//! sampled and given a density by random walks through the slab (Guo, Hasan and Zhao 2018,
//! "Position-free Monte Carlo simulation for arbitrary layered BSDFs"; the estimators of
//! pbrt-v4 §14.3).
//!
//! - `eval` is an unbiased estimate of f: walks enter through the coat towards wo and are
//!   joined at each bounce to a transmission through the coat towards wi sampled from wi's
//!   side (light's direction of travel), combined by the power heuristic with the walk's own
//!   next bounce.
//! - `sample` follows one walk from wo until it leaves through the coat; its weight is the
//!   walk's f |cos| / pdf.
//! - `pdf` is pbrt-v4's stochastic approximation of the density `sample` has (one round trip
//!   through the base, mixed with 1/4pi), good enough for MIS weights, which only need every
//!   technique to see the same value.
//!
//! Each estimate draws its numbers from a stream seeded by its arguments, so the same
//! arguments give the same value, on any thread, and `sample`'s density is `pdf`'s value at
//! the direction it returns.

mod base;
mod coat;
mod phase;

use super::scatter::{Lobes, Mode, Scatter};
use super::{BsdfSample, RoughConductor};
use base::Base;
use coat::Coat;
use fenestra_core::mis::MisHeuristic;
use fenestra_core::rng::Rng;
use fenestra_core::{Rgb, Vec2, Vec3, INV_PI};
use fenestra_scene::material::{self, Layers, SMOOTH_ALPHA};
use phase::HenyeyGreenstein;

/// The heuristic that joins a walk's bounces to the exit (pbrt-v4's).
const POWER: MisHeuristic = MisHeuristic::Power { beta: 2.0 };

/// A coat over a base with a slab between them, both directions above the surface.
#[derive(Clone, Debug)]
pub struct Layered {
    coat: Coat,
    base: Base,
    thickness: f32,
    albedo: Rgb,
    phase: HenyeyGreenstein,
    max_depth: u32,
    samples: u32,
}

/// Where a flight through the slab's medium ends.
enum Flight {
    /// Scattered inside the slab at this height.
    Scattered(f32),
    /// Reached the coat (height = thickness) or the base (0).
    Boundary(f32),
}

impl Layered {
    fn new(coat: Coat, base: Base, layers: &Layers) -> Self {
        Layered {
            coat,
            base,
            thickness: layers.thickness.max(f32::MIN_POSITIVE),
            albedo: layers.albedo,
            phase: HenyeyGreenstein { g: layers.g },
            max_depth: layers.max_depth,
            samples: layers.samples.max(1),
        }
    }

    /// pbrt-v4's coateddiffuse: a Lambertian base of albedo `reflectance` under a coat of
    /// index `eta` and GGX roughness `alpha`.
    pub fn coated_diffuse(reflectance: Rgb, eta: f32, alpha: f32, layers: &Layers) -> Self {
        Self::new(Coat::new(eta, alpha), Base::Diffuse(reflectance), layers)
    }

    /// The same layers over a Lambertian base of another albedo (a texture's value at a hit),
    /// clamped to [0, 1] as pbrt-v4 clamps reflectances.
    pub fn with_base_reflectance(&self, reflectance: Rgb) -> Self {
        Layered {
            base: Base::Diffuse(reflectance.map(|c| c.clamp(0.0, 1.0))),
            ..self.clone()
        }
    }

    /// pbrt-v4's coatedconductor. The conductor's index is relative to the slab's, as pbrt-v4
    /// takes it: eta / eta_coat and k / eta_coat.
    pub fn coated_conductor(m: &material::CoatedConductor) -> Self {
        let (eta, k) = (m.eta / m.interface_eta, m.k / m.interface_eta);
        let base = if m.alpha_x.max(m.alpha_y) <= SMOOTH_ALPHA {
            Base::SmoothConductor { eta, k }
        } else {
            Base::RoughConductor(RoughConductor::new(eta, k, m.alpha_x, m.alpha_y))
        };
        Self::new(
            Coat::new(m.interface_eta, m.interface_alpha),
            base,
            &m.layers,
        )
    }

    /// Whether f depends on the tangent's direction (a rough conductor base may be anisotropic).
    pub fn needs_tangent(&self) -> bool {
        matches!(self.base, Base::RoughConductor(_))
    }

    /// Whether every path through the layers is a Dirac one (smooth coat over a smooth base).
    pub fn is_delta(&self) -> bool {
        self.coat.is_specular() && self.base.is_specular() && self.albedo == Rgb::ZERO
    }

    /// Transmittance across the slab's height `dz` along `w`.
    fn tr(dz: f32, w: Vec3) -> f32 {
        if dz.abs() <= f32::MIN_POSITIVE {
            1.0
        } else {
            (-(dz / w.z).abs()).exp()
        }
    }

    /// A free flight from height `z` along `w` through the slab's medium (extinction 1).
    fn fly(&self, z: f32, w: Vec3, u: f32) -> Option<Flight> {
        let dz = -(1.0 - u).ln() * w.z.abs();
        let zp = if w.z > 0.0 { z + dz } else { z - dz };
        if zp == z {
            None
        } else if 0.0 < zp && zp < self.thickness {
            Some(Flight::Scattered(zp))
        } else {
            Some(Flight::Boundary(zp.clamp(0.0, self.thickness)))
        }
    }

    /// Russian roulette on a walk of throughput `beta` after `depth` bounces: `Some(scale)` to
    /// go on with, `None` to stop (pbrt-v4's rule).
    fn survives(depth: u32, beta: f32, rng: &mut Rng) -> Option<f32> {
        if depth <= 3 || beta >= 0.25 {
            return Some(1.0);
        }
        let q = (1.0 - beta).max(0.0);
        (rng.next_f32() >= q).then(|| 1.0 / (1.0 - q))
    }

    /// f(wo, wi) estimated by `samples` walks (pbrt-v4 §14.3.2).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let mut rng = stream(wo, wi.to_array());
        let n = self.samples as f32;
        let mut f = Rgb::splat(n * self.coat.f(wo, wi, Mode::Radiance));
        for _ in 0..self.samples {
            if let Some((wos, wis)) = self.through_coat(wo, wi, &mut rng) {
                f += self.walk_to(wi, wos, wis, &mut rng);
            }
        }
        f / n
    }

    /// Transmissions through the coat into the slab: from `wo`'s side as the walk's entrance
    /// (radiance) and from `wi`'s side as its exit (importance, light's direction of travel).
    fn through_coat(&self, wo: Vec3, wi: Vec3, rng: &mut Rng) -> Option<(Scatter, Scatter)> {
        let mut into = |w: Vec3, mode: Mode| {
            let uc = rng.next_f32();
            self.coat
                .sample(w, uc, rng.next_2d(), mode, Lobes::Transmission)
        };
        let wos = into(wo, Mode::Radiance);
        let wis = into(wi, Mode::Importance);
        wos.zip(wis)
    }

    /// One walk's estimate of f: entered through the coat by `wos`, joined at every bounce to
    /// the exit `wis` (sampled from wi's side) and to the coat's f towards `wi`.
    fn walk_to(&self, wi: Vec3, wos: Scatter, wis: Scatter, rng: &mut Rng) -> Rgb {
        let top = self.thickness;
        let exit = wis.f * (1.0 / wis.pdf);
        let mut f = Rgb::ZERO;
        let mut beta = wos.weight();
        let (mut z, mut w) = (top, wos.wi);
        // The bounces of iteration `depth` leave the slab at `sample`'s iteration depth + 1,
        // which must come before its max_depth (pbrt-v4 lets f go one order further than its
        // sampling).
        for depth in 0..self.max_depth.saturating_sub(1) {
            match Self::survives(depth, beta.max_component(), rng) {
                Some(scale) => beta *= scale,
                None => break,
            }
            if self.albedo == Rgb::ZERO {
                z = if z == top { 0.0 } else { top };
                beta *= Self::tr(top, w);
            } else {
                match self.fly(z, w, rng.next_f32()) {
                    None => continue,
                    Some(Flight::Boundary(zb)) => z = zb,
                    Some(Flight::Scattered(zp)) => {
                        // Light scattered by the medium towards the exit (§14.3.2's NEE).
                        let p = self.phase.p(-w, -wis.wi);
                        let wt = self.joined(wis.pdf, p);
                        f += beta * self.albedo * exit * (p * wt * Self::tr(zp - top, wis.wi));
                        let (wn, pp) = self.phase.sample(-w, rng.next_2d());
                        if pp == 0.0 || wn.z == 0.0 {
                            continue;
                        }
                        beta *= self.albedo;
                        (w, z) = (wn, zp);
                        if w.z > 0.0 && !self.coat.is_specular() {
                            let f_exit = self.coat.f(-w, wi, Mode::Radiance);
                            if f_exit > 0.0 {
                                let wt = POWER.weight(pp, self.exit_pdf(wi, w));
                                f += beta * (Self::tr(zp - top, w) * f_exit * wt);
                            }
                        }
                        continue;
                    }
                }
            }
            if z == top {
                // Back down off the coat's underside.
                let Some(s) = self.coat.sample(
                    -w,
                    rng.next_f32(),
                    rng.next_2d(),
                    Mode::Radiance,
                    Lobes::Reflection,
                ) else {
                    break;
                };
                beta *= s.weight();
                w = s.wi;
                continue;
            }
            // At the base: joined to the exit, then reflected up.
            if !self.base.is_specular() {
                let fb = self.base.f(-w, -wis.wi);
                let wt = self.joined(wis.pdf, self.base.pdf(-w, -wis.wi));
                let across = wis.wi.z.abs() * wt * Self::tr(top, wis.wi);
                f += beta * fb * exit * across;
            }
            let Some(s) = self.base.sample(-w, rng.next_2d()) else {
                break;
            };
            beta *= s.weight();
            w = s.wi;
            if !self.coat.is_specular() {
                let f_exit = self.coat.f(-w, wi, Mode::Radiance);
                if f_exit > 0.0 {
                    let wt = if self.base.is_specular() {
                        1.0
                    } else {
                        POWER.weight(s.pdf, self.exit_pdf(wi, w))
                    };
                    f += beta * (Self::tr(top, w) * f_exit * wt);
                }
            }
        }
        f
    }

    /// The density with which the exit sampled from `wi`'s side gives the inner direction `w`
    /// (travelling up): the other technique's density for a bounce that leaves along `w`,
    /// in the same measure. pbrt-v4 weighs these bounces with the density of refracting
    /// from `w` to `wi` instead, another measure, so its weights do not add up to one and its
    /// f is brighter than its sampling under rough coats (7.7% over a white-ish base; see
    /// tests/layered.rs and pbrt-v4's issue 187).
    fn exit_pdf(&self, wi: Vec3, w: Vec3) -> f32 {
        self.coat.pdf(wi, -w, Lobes::Transmission)
    }

    /// The weight of joining to the exit sampled with density `exit_pdf` against the walk's
    /// own bounce of density `bounce_pdf`: 1 through a smooth coat (the walk cannot hit it).
    fn joined(&self, exit_pdf: f32, bounce_pdf: f32) -> f32 {
        if self.coat.is_specular() {
            1.0
        } else {
            POWER.weight(exit_pdf, bounce_pdf)
        }
    }

    /// A smooth, deterministic stand-in for [`Layered::pdf`] (the coat's reflection and a
    /// cosine lobe, half each), for MIS weights that two strategies must compute alike: the
    /// estimate's stream is seeded by the directions' bits, which two paths through the same
    /// vertices do not share.
    pub fn mis_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        0.5 * (self.coat.pdf(wo, wi, Lobes::Reflection) + wi.z.abs() * INV_PI)
    }

    /// pbrt-v4's approximate density of `sample` (§14.3.3): the coat's reflection plus one
    /// round trip through the base, mixed with the uniform sphere's 1/4pi.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let mut rng = stream(wi, wo.to_array());
        let n = self.samples as f32;
        let mut sum = n * self.coat.pdf(wo, wi, Lobes::Reflection);
        for _ in 0..self.samples {
            let Some((wos, wis)) = self.through_coat(wo, wi, &mut rng) else {
                continue;
            };
            if self.coat.is_specular() {
                sum += self.base.pdf(-wos.wi, -wis.wi);
                continue;
            }
            let Some(rs) = self.base.sample(-wos.wi, rng.next_2d()) else {
                continue;
            };
            let t_pdf = self.coat.pdf(-rs.wi, wi, Lobes::All);
            if self.base.is_specular() {
                sum += t_pdf;
            } else {
                let r_pdf = self.base.pdf(-wos.wi, -wis.wi);
                sum += POWER.weight(wis.pdf, r_pdf) * r_pdf;
                sum += POWER.weight(rs.pdf, t_pdf) * t_pdf;
            }
        }
        0.1 * 0.25 * INV_PI + 0.9 * sum / n
    }

    /// Samples an incident direction for `wo` by one walk through the layers (§14.3.3).
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let first = self.coat.sample(wo, uc, u, Mode::Radiance, Lobes::All)?;
        if first.wi.z > 0.0 {
            return Some(self.sampled(wo, first.wi, first.weight(), first.pdf, first.specular));
        }
        let mut rng = stream(wo, [uc, u.x, u.y]);
        let top = self.thickness;
        let mut specular = first.specular;
        let mut f = first.f * first.wi.z.abs();
        let mut pdf = first.pdf;
        let (mut z, mut w) = (top, first.wi);
        for depth in 0..self.max_depth {
            pdf /= Self::survives(depth, f.max_component() / pdf, &mut rng)?;
            if self.albedo == Rgb::ZERO {
                z = if z == top { 0.0 } else { top };
                f *= Self::tr(top, w);
            } else {
                match self.fly(z, w, rng.next_f32())? {
                    Flight::Boundary(zb) => z = zb,
                    Flight::Scattered(zp) => {
                        let (wn, pp) = self.phase.sample(-w, rng.next_2d());
                        if pp == 0.0 || wn.z == 0.0 {
                            return None;
                        }
                        f *= self.albedo * pp;
                        pdf *= pp;
                        specular = false;
                        (w, z) = (wn, zp);
                        continue;
                    }
                }
            }
            let s = if z == 0.0 {
                self.base.sample(-w, rng.next_2d())
            } else {
                let uc = rng.next_f32();
                self.coat
                    .sample(-w, uc, rng.next_2d(), Mode::Radiance, Lobes::All)
            }?;
            f *= s.f;
            pdf *= s.pdf;
            specular &= s.specular;
            w = s.wi;
            if z == top && w.z > 0.0 {
                // Out through the coat.
                return Some(self.sampled(wo, w, f * (w.z / pdf), pdf, specular));
            }
            f *= w.z.abs();
        }
        None
    }

    /// A sample leaving towards `wi` with the walk's weight; its density for MIS is `pdf`'s
    /// value there (a Dirac path keeps its discrete probability).
    fn sampled(&self, wo: Vec3, wi: Vec3, weight: Rgb, walk_pdf: f32, delta: bool) -> BsdfSample {
        BsdfSample {
            wi,
            weight,
            pdf: if delta { walk_pdf } else { self.pdf(wo, wi) },
            delta,
        }
    }
}

/// A random stream seeded by a direction and three more numbers.
fn stream(a: Vec3, b: [f32; 3]) -> Rng {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for x in [a.x, a.y, a.z, b[0], b[1], b[2]] {
        h = (h ^ u64::from(x.to_bits())).wrapping_mul(0x0000_0100_0000_01b3);
        h ^= h >> 29;
    }
    Rng::new(h)
}

impl From<&material::CoatedDiffuse> for Layered {
    /// The base texture's mean stands in until a hit point's lookup replaces it
    /// (`RenderScene::bsdf_at`).
    fn from(m: &material::CoatedDiffuse) -> Self {
        Layered::coated_diffuse(m.reflectance, m.eta, m.alpha, &m.layers)
    }
}

impl From<&material::CoatedConductor> for Layered {
    fn from(m: &material::CoatedConductor) -> Self {
        Layered::coated_conductor(m)
    }
}
