//! The irradiance cache for diffuse surfaces (Ward et al. 1988, with the rotation and
//! translation gradients of Ward and Heckbert 1992 in the form of Krivanek et al. 2008), as
//! seed 003 §2.5 uses it for diffuse indirect light beside SDRC: a record holds the
//! irradiance from reflected light at its point, estimated from a stratified cosine-weighted
//! hemisphere; between records it is extrapolated by the gradients and averaged with the
//! weights of eq. 2.2.

use crate::kind::CacheKind;
use crate::options::Gradients;
use crate::record::{Payload, Record};
use crate::record_rays::{viewer_geometric_normal, viewer_normal, Distances, RecordRays};
use crate::spatial::{Delta, SpatialCache};
use fenestra_core::stats::RayCounters;
use fenestra_core::{Frame, Rgb, Vec3};
use fenestra_render::integrator::Shading;
use fenestra_render::RenderScene;
use std::f32::consts::{PI, TAU};

/// Seed of the irradiance records' sample streams (xor-ed with the render's seed).
const RECORD_RAYS: u64 = 0x5d5c_0004;

/// Irradiance at a record and its gradients (world vectors, one a channel).
#[derive(Clone, Copy, Debug)]
pub struct Irradiance {
    /// Irradiance from light reflected by other surfaces.
    pub e: Rgb,
    /// Change with the normal's rotation: E(n) ~ E + (n_i x n) . rotation.
    pub rotation: [Vec3; 3],
    /// Change with the point's translation: E(p) ~ E + (p - p_i) . translation.
    pub translation: [Vec3; 3],
}

impl Payload for Irradiance {
    /// Irradiance records are never added to.
    type Update = ();

    fn absorb(&mut self, _: ()) {}

    fn bytes(&self) -> usize {
        0
    }
}

impl Irradiance {
    /// The irradiance extrapolated from record `r` (holding `self`) to a point `p` with
    /// normal `n` by the gradients `use_`.
    fn at(&self, r: &Record<Irradiance>, p: Vec3, n: Vec3, use_: Gradients) -> Rgb {
        let turn = match use_ {
            Gradients::None => Vec3::ZERO,
            Gradients::Rotation | Gradients::Both => r.frame.n.cross(n),
        };
        let moved = match use_ {
            Gradients::Both => p - r.si.p,
            Gradients::None | Gradients::Rotation => Vec3::ZERO,
        };
        let channel =
            |c: usize, e: f32| e + turn.dot(self.rotation[c]) + moved.dot(self.translation[c]);
        Rgb::new(
            channel(0, self.e.r),
            channel(1, self.e.g),
            channel(2, self.e.b),
        )
        .map(|v| v.max(0.0))
    }
}

/// Irradiance records and the options they follow.
#[derive(Clone, Copy, Debug)]
pub(crate) struct IrradianceRecords {
    /// Rays per record.
    pub(crate) rays: u32,
    /// Which gradients records keep and use.
    pub(crate) gradients: Gradients,
}

impl CacheKind for IrradianceRecords {
    type Payload = Irradiance;

    /// A new irradiance record at `s`: M x N stratified cosine-weighted directions (N ~ pi M),
    /// their reflected radiance, the irradiance E = pi / (M N) sum L and its gradients; R_i
    /// from the hit distances, limited where the irradiance changes faster (E / |grad E|).
    fn create(
        &self,
        tracing: &mut RecordRays,
        delta: &mut Delta<Irradiance>,
        scene: &RenderScene,
        s: &Shading,
        a: f32,
        rays: &mut RayCounters,
    ) -> Record<Irradiance> {
        let frame = Frame::from_normal(viewer_normal(s));
        let ng = viewer_geometric_normal(s);
        let rings = ((self.rays as f32 / PI).sqrt().round() as usize).max(2);
        let sectors = (self.rays as usize / rings).max(3);
        let mut distances = Distances::default();
        // Cosine-weighted: sin^2 theta uniform over the ring's share.
        let cosine = |sin2: f32| (sin2.sqrt(), (1.0 - sin2).max(0.0).sqrt());
        let cells = tracing.stratified(
            scene,
            s,
            (&frame, ng),
            RECORD_RAYS,
            (rings, sectors),
            cosine,
            rays,
            &mut distances,
        );
        delta.counts.record_rays += cells.len() as u64;
        let cells: Vec<_> = cells.iter().map(|c| (c.l, c.t, c.sin, c.phi)).collect();
        let irradiance = gradients(&cells, rings, sectors, &frame);
        let e = irradiance.e.luminance();
        let translation = self.gradients == Gradients::Both;
        let relative = (e > 0.0 && translation).then(|| {
            let g = luminance_of(&irradiance.translation);
            g.length() / e
        });
        Record {
            si: *s.si,
            frame,
            ng,
            r: tracing.radius(s, a, &distances, relative),
            payload: irradiance,
            pixel: (s.sample.x, s.sample.y),
        }
    }

    /// Irradiance at `s` from the records near: their gradient-extrapolated values averaged
    /// with the weights of eq. 2.2.
    fn interpolate(
        &self,
        _: &mut RecordRays,
        cache: &SpatialCache<Irradiance>,
        delta: &mut Delta<Irradiance>,
        _: &RenderScene,
        s: &Shading,
        _: &mut RayCounters,
    ) -> Rgb {
        let n = viewer_normal(s);
        let (mut sum, mut total) = (Rgb::ZERO, 0.0f32);
        for &(id, w) in &delta.near {
            let r = cache.record(delta, id);
            sum += r.payload.at(r, s.si.p, n, self.gradients) * w;
            total += w;
        }
        if total > 0.0 {
            sum * (1.0 / total)
        } else {
            Rgb::ZERO
        }
    }
}

/// Irradiance and its gradients from the cells of a stratified cosine-weighted hemisphere
/// (`cells[j * sectors + k]`: radiance, hit distance, sin theta, phi of ring j and sector k;
/// Krivanek et al. 2008 eq. 2.17-2.19 for the cosine-weighted strata).
fn gradients(
    cells: &[(Rgb, f32, f32, f32)],
    rings: usize,
    sectors: usize,
    frame: &Frame,
) -> Irradiance {
    let (m, nn) = (rings as f32, sectors as f32);
    let cell = |j: usize, k: usize| cells[j * sectors + k];
    let mut e = Rgb::ZERO;
    let mut rotation = [Vec3::ZERO; 3];
    let mut translation = [Vec3::ZERO; 3];
    let add = |acc: &mut [Vec3; 3], v: Vec3, c: Rgb| {
        acc[0] += v * c.r;
        acc[1] += v * c.g;
        acc[2] += v * c.b;
    };
    for k in 0..sectors {
        // Sector k's centre direction u_k and the direction v_k- across its lower boundary.
        let phi_mid = TAU * (k as f32 + 0.5) / nn;
        let phi_edge = TAU * k as f32 / nn;
        let u_k = Vec3::new(phi_mid.cos(), phi_mid.sin(), 0.0);
        let v_edge = Vec3::new(-phi_edge.sin(), phi_edge.cos(), 0.0);
        let previous = (k + sectors - 1) % sectors;
        for j in 0..rings {
            let (l, t, sin, phi) = cell(j, k);
            e += l;
            // Rotation: turning n by the small angle vector d changes E by d . G with
            // G = integral of L (n x w) dw (the horizon moves only where cos = 0), and
            // n x w = sin theta (-sin phi, cos phi, 0): as a cosine-weighted estimate,
            // pi / (M N) sum tan theta L (-sin phi, cos phi, 0). (d = n_i x n.)
            let cos = (1.0 - sin * sin).max(1e-6).sqrt();
            let v = Vec3::new(-phi.sin(), phi.cos(), 0.0);
            add(&mut rotation, v * (sin / cos), l);
            // Translation across the ring boundary below ring j (between rings j-1 and j).
            let sin2_edge = j as f32 / m;
            if j > 0 {
                let (l_in, t_in, ..) = cell(j - 1, k);
                let d = t.min(t_in);
                if d.is_finite() && d > 0.0 {
                    let f = (TAU / nn) * sin2_edge.sqrt() * (1.0 - sin2_edge) / d;
                    add(&mut translation, u_k * f, l - l_in);
                }
            }
            // Translation across the sector boundary (between sectors k-1 and k).
            let (l_side, t_side, ..) = cell(j, previous);
            let d = t.min(t_side);
            let sin_mid = ((j as f32 + 0.5) / m).sqrt();
            if d.is_finite() && d > 0.0 {
                let cos_lo = (1.0 - sin2_edge).sqrt();
                let cos_hi = (1.0 - (j as f32 + 1.0) / m).max(0.0).sqrt();
                let f = (cos_lo - cos_hi) / (sin_mid * d);
                add(&mut translation, v_edge * f, l - l_side);
            }
        }
    }
    let scale = PI / (m * nn);
    Irradiance {
        e: e * scale,
        rotation: rotation.map(|v| frame.to_world(v * scale)),
        translation: translation.map(|v| frame.to_world(v)),
    }
}

/// The luminance of a gradient given per channel (the weights of [`Rgb::luminance`]).
fn luminance_of(g: &[Vec3; 3]) -> Vec3 {
    g[0] * 0.2126 + g[1] * 0.7152 + g[2] * 0.0722
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cells (at their centres) of a hemisphere lit by L(w) = 1 + w.x w.z (local frame),
    /// with the distance `t`.
    fn cells(rings: usize, sectors: usize, t: f32) -> Vec<(Rgb, f32, f32, f32)> {
        let mut cells = Vec::new();
        for j in 0..rings {
            for k in 0..sectors {
                let sin = ((j as f32 + 0.5) / rings as f32).sqrt();
                let cos = (1.0 - sin * sin).sqrt();
                let phi = TAU * (k as f32 + 0.5) / sectors as f32;
                cells.push((Rgb::splat(1.0 + sin * phi.cos() * cos), t, sin, phi));
            }
        }
        cells
    }

    #[test]
    fn irradiance_and_its_rotation_gradient_match_the_integrals() {
        // E = integral of L cos = pi (w.x w.z cos is odd in x); turning n by d about y
        // (towards +x) changes E by d . G with G = integral of L (n x w) dw, whose y part is
        // integral of w.x w.z sin theta cos phi = pi / 4.
        let frame = Frame::from_normal(Vec3::Z);
        let g = gradients(&cells(64, 200, 1.0), 64, 200, &frame);
        assert!((g.e.r - PI).abs() < 1e-3 * PI, "E {}", g.e.r);
        let d = 0.01f32;
        let turn = Vec3::Z.cross(Vec3::new(d.sin(), 0.0, d.cos()));
        let predicted = turn.dot(g.rotation[0]) / d.sin();
        let exact = PI / 4.0;
        assert!(
            (predicted - exact).abs() < 0.01 * exact,
            "dE/dd {predicted}, {exact}"
        );
    }

    #[test]
    fn uniform_radiance_has_no_gradients() {
        let frame = Frame::from_normal(Vec3::new(0.3, -0.2, 0.9).normalize());
        let mut c = cells(8, 25, 0.5);
        c.iter_mut().for_each(|c| c.0 = Rgb::splat(2.0));
        let g = gradients(&c, 8, 25, &frame);
        assert!((g.e.g - 2.0 * PI).abs() < 1e-4);
        assert!(g.translation[1].length() < 1e-4, "{:?}", g.translation);
        // Uniform light has a rotation gradient only through the cells' tan theta, whose
        // sum over full rings of sectors vanishes.
        assert!(g.rotation[1].length() < 1e-3, "{:?}", g.rotation);
    }
}
