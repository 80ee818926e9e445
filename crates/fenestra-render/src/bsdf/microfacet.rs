//! Anisotropic GGX (Trowbridge-Reitz) microfacet distribution with height-correlated Smith
//! masking and visible-normal sampling (Heitz 2018).

use fenestra_core::{Vec2, Vec3, PI};

#[derive(Clone, Copy, Debug)]
pub struct Ggx {
    pub ax: f32,
    pub ay: f32,
}

impl Ggx {
    /// Roughness is clamped away from zero, where the distribution degenerates to a delta.
    pub fn new(ax: f32, ay: f32) -> Self {
        Ggx {
            ax: ax.max(1e-3),
            ay: ay.max(1e-3),
        }
    }

    /// D(h) for a unit half vector in the upper hemisphere.
    pub fn d(&self, h: Vec3) -> f32 {
        if h.z <= 0.0 {
            return 0.0;
        }
        let e = (h.x / self.ax).powi(2) + (h.y / self.ay).powi(2) + h.z * h.z;
        1.0 / (PI * self.ax * self.ay * e * e)
    }

    fn lambda(&self, w: Vec3) -> f32 {
        if w.z == 0.0 {
            return f32::INFINITY;
        }
        let a2t2 = ((w.x * self.ax).powi(2) + (w.y * self.ay).powi(2)) / (w.z * w.z);
        0.5 * ((1.0 + a2t2).sqrt() - 1.0)
    }

    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// Density of the visible normal `h` seen from `w`: G1(w) |w.h| D(h) / |w.z|.
    pub fn pdf_visible(&self, w: Vec3, h: Vec3) -> f32 {
        if w.z == 0.0 {
            return 0.0;
        }
        self.g1(w) * w.dot(h).abs() * self.d(h) / w.z.abs()
    }

    /// Samples a visible normal from `w` (either hemisphere; the normal is in the upper one).
    pub fn sample_visible(&self, w: Vec3, u: Vec2) -> Vec3 {
        let mut wh = Vec3::new(self.ax * w.x, self.ay * w.y, w.z).normalize();
        if wh.z < 0.0 {
            wh = -wh;
        }
        let t1 = if wh.z < 0.99999 {
            Vec3::Z.cross(wh).normalize()
        } else {
            Vec3::X
        };
        let t2 = wh.cross(t1);
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let (p1, mut p2) = (r * phi.cos(), r * phi.sin());
        let s = 0.5 * (1.0 + wh.z);
        p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * wh;
        Vec3::new(self.ax * nh.x, self.ay * nh.y, nh.z.max(1e-6)).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projected_ndf_integrates_to_one() {
        // int D(h) cos(theta_h) dw = 1, by midpoint rule in (cos theta, phi).
        for (ax, ay) in [(0.1, 0.1), (0.3, 0.05), (0.8, 0.5)] {
            let g = Ggx::new(ax, ay);
            let (nt, np) = (2000, 200);
            let mut sum = 0.0f64;
            for i in 0..nt {
                // Substitution cos t = 1 - s^4 concentrates points near the normal.
                let sv = (i as f64 + 0.5) / nt as f64;
                let c = 1.0 - sv.powi(4);
                let dc = 4.0 * sv.powi(3) / nt as f64;
                let st = (1.0 - c * c).sqrt();
                for j in 0..np {
                    let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / np as f64;
                    let h = Vec3::new((st * phi.cos()) as f32, (st * phi.sin()) as f32, c as f32);
                    sum += g.d(h) as f64 * c * dc * 2.0 * std::f64::consts::PI / np as f64;
                }
            }
            assert!((sum - 1.0).abs() < 0.01, "({ax}, {ay}): {sum}");
        }
    }
}
