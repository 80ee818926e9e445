//! The Henyey-Greenstein phase function of the slab's medium, in pbrt-v4's convention: both
//! directions point away from the scattering point, so forward scattering (g > 0) favours
//! wi = -wo.

use fenestra_core::{Frame, Vec2, Vec3, INV_PI, PI};

/// Henyey and Greenstein (1941) with asymmetry `g` in (-1, 1).
#[derive(Clone, Copy, Debug)]
pub(super) struct HenyeyGreenstein {
    pub g: f32,
}

impl HenyeyGreenstein {
    /// p(wo, wi), which is also the density `sample` gives wi with.
    pub(super) fn p(&self, wo: Vec3, wi: Vec3) -> f32 {
        let g = self.g;
        let denom = 1.0 + g * g + 2.0 * g * wo.dot(wi);
        0.25 * INV_PI * (1.0 - g * g) / (denom * denom.max(0.0).sqrt())
    }

    /// Samples wi for `wo` exactly in proportion to p: the cosine to the forward direction
    /// -wo by inverting HG's distribution.
    pub(super) fn sample(&self, wo: Vec3, u: Vec2) -> (Vec3, f32) {
        let g = self.g;
        let cos = if g.abs() < 1e-3 {
            1.0 - 2.0 * u.x
        } else {
            let s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);
            (1.0 + g * g - s * s) / (2.0 * g)
        }
        .clamp(-1.0, 1.0);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let local = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
        let wi = Frame::from_normal(-wo).to_world(local);
        (wi, self.p(wo, wi))
    }
}
