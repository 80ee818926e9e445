//! Uniform sampling of the solid angle a rectangle subtends (Urena, Fajardo and King 2013,
//! "An area-preserving parametrization for spherical rectangles"): beyond seed 000's area
//! sampling, every direction through the portal gets the same density 1/S, so near portals
//! seen at grazing angles no longer waste samples on their far side.

use fenestra_core::{trig, Vec2, Vec3, PI};
use glam::Vec4;

/// A rectangle as seen from a point, ready to sample.
#[derive(Clone, Copy, Debug)]
pub struct SphericalRectangle {
    o: Vec3,
    x: Vec3,
    y: Vec3,
    z: Vec3,
    z0: f32,
    x0: f32,
    x1: f32,
    y0: f32,
    y1: f32,
    b0: f32,
    b1: f32,
    k: f32,
    /// Solid angle (sr).
    pub solid_angle: f32,
}

impl SphericalRectangle {
    /// The rectangle corner + s ex + t ey, (s, t) in [0, 1]^2 with ex perpendicular to ey,
    /// seen from `o`; `None` when `o` lies in its plane.
    pub fn new(o: Vec3, corner: Vec3, ex: Vec3, ey: Vec3) -> Option<Self> {
        let (lx, ly) = (ex.length(), ey.length());
        let (x, y) = (ex / lx, ey / ly);
        let mut z = x.cross(y);
        let d = corner - o;
        let mut z0 = d.dot(z);
        // The local frame puts the rectangle below the point (z0 < 0).
        if z0 > 0.0 {
            z0 = -z0;
            z = -z;
        }
        if !(z0 < -1e-7 * (lx + ly)) {
            return None;
        }
        let (x0, y0) = (d.dot(x), d.dot(y));
        let (x1, y1) = (x0 + lx, y0 + ly);
        // The z components of the unit normals of the four planes through o and an edge
        // ((0, z0, -y0), (-z0, 0, x1), (0, -z0, y1), (z0, 0, -x0), normalised), four at once,
        // and the interior angles between neighbouring planes.
        let along = Vec4::new(-y0, x1, y1, -x0);
        let nz = along / (along * along + z0 * z0).sqrt();
        let g = trig::acos4(-nz * Vec4::new(nz.y, nz.z, nz.w, nz.x));
        let k = 2.0 * PI - g.z - g.w;
        let solid_angle = g.x + g.y - k;
        (solid_angle > 0.0 && solid_angle.is_finite()).then_some(SphericalRectangle {
            o,
            x,
            y,
            z,
            z0,
            x0,
            x1,
            y0,
            y1,
            b0: nz.x,
            b1: nz.z,
            k,
            solid_angle,
        })
    }

    /// A point on the rectangle whose direction from `o` is uniform in solid angle.
    pub fn sample(&self, u: Vec2) -> Vec3 {
        let au = u.x * self.solid_angle + self.k;
        let (sin, cos) = trig::sin_cos(au);
        let fu = (cos * self.b0 - self.b1) / sin;
        // Urena et al. take cu = sign(fu) / sqrt(fu^2 + b0^2) and xu = -cu z0 / sqrt(1 - cu^2),
        // which is -sign(fu) z0 / sqrt(fu^2 + b0^2 - 1): one root and one division fewer
        // (1 - cu^2 is kept from vanishing as they keep it).
        let t = fu * fu + self.b0 * self.b0;
        let xu =
            ((-self.z0).copysign(fu) / (t - 1.0).max(1e-12 * t).sqrt()).clamp(self.x0, self.x1);
        let d2 = xu * xu + self.z0 * self.z0;
        let h0 = self.y0 / (d2 + self.y0 * self.y0).sqrt();
        let h1 = self.y1 / (d2 + self.y1 * self.y1).sqrt();
        let hv = h0 + u.y * (h1 - h0);
        let hv2 = hv * hv;
        let yv = if hv2 < 1.0 - 1e-6 {
            (hv * (d2 / (1.0 - hv2)).sqrt()).clamp(self.y0, self.y1)
        } else {
            self.y1
        };
        self.o + self.x * xu + self.y * yv + self.z * self.z0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect() -> (Vec3, Vec3, Vec3) {
        (
            Vec3::new(-0.3, 0.2, 1.0),
            Vec3::new(0.8, 0.0, 0.3),
            Vec3::new(0.0, 0.5, 0.0),
        )
    }

    #[test]
    fn solid_angle_matches_numerical_integration() {
        let (c, ex, ey) = rect();
        let o = Vec3::new(0.1, -0.4, -0.2);
        let sr = SphericalRectangle::new(o, c, ex, ey).expect("visible");
        // Integrate |cos| / r^2 over the rectangle's area on a fine grid.
        let n = 400;
        let area = ex.cross(ey).length();
        let nrm = ex.cross(ey).normalize();
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let p = c + ex * ((i as f32 + 0.5) / n as f32) + ey * ((j as f32 + 0.5) / n as f32);
                let d = p - o;
                sum += (d.normalize().dot(nrm).abs() / d.length_squared()) as f64;
            }
        }
        let expected = sum * area as f64 / (n * n) as f64;
        assert!(
            (sr.solid_angle as f64 / expected - 1.0).abs() < 1e-3,
            "{} vs {expected}",
            sr.solid_angle
        );
    }

    #[test]
    fn samples_are_uniform_in_solid_angle() {
        // Chi-square over a 6x6 grid of the rectangle: the expected count of a cell is its
        // solid angle over the whole one (numerically integrated), times the sample count.
        let (c, ex, ey) = rect();
        let o = Vec3::new(0.9, -0.1, 0.6);
        let sr = SphericalRectangle::new(o, c, ex, ey).expect("visible");
        let cells = 6;
        let n = 60_000u32;
        let mut counts = vec![0f64; cells * cells];
        let (lx2, ly2) = (ex.length_squared(), ey.length_squared());
        for i in 0..n {
            let u = Vec2::new(
                fenestra_core::sampler::hash_u32(i) as f32 / 4_294_967_296.0,
                fenestra_core::sampler::hash_u32(i ^ 0x5555_aaaa) as f32 / 4_294_967_296.0,
            );
            let p = sr.sample(u) - c;
            let (s, t) = (p.dot(ex) / lx2, p.dot(ey) / ly2);
            assert!(
                (-1e-4..=1.0001).contains(&s) && (-1e-4..=1.0001).contains(&t),
                "{s} {t}"
            );
            let (a, b) = (
                ((s * cells as f32) as usize).min(cells - 1),
                ((t * cells as f32) as usize).min(cells - 1),
            );
            counts[a * cells + b] += 1.0;
        }
        let mut expected = vec![0.0; cells * cells];
        for a in 0..cells {
            for b in 0..cells {
                let cell = SphericalRectangle::new(
                    o,
                    c + ex * (a as f32 / cells as f32) + ey * (b as f32 / cells as f32),
                    ex / cells as f32,
                    ey / cells as f32,
                )
                .expect("cell");
                expected[a * cells + b] = n as f64 * (cell.solid_angle / sr.solid_angle) as f64;
            }
        }
        let fit = fenestra_eval::chi2::chi2(&counts, &expected, 0.0).expect("same bins");
        assert!(fit.p_value > 1e-3, "{fit:?}");
    }
}
