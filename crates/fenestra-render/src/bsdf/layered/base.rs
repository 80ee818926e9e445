//! The opaque base under a coat, lit from inside the slab: Lambertian, or a conductor
//! (smooth, or GGX-rough) whose index is relative to the slab's.

use super::super::scatter::Scatter;
use super::super::{fresnel, reflect_z, RoughConductor};
use fenestra_core::{warp, Rgb, Vec2, Vec3, INV_PI};

/// A layered material's base (reflection only; `wo` above it).
#[derive(Clone, Debug)]
pub(super) enum Base {
    /// Lambertian of this albedo.
    Diffuse(Rgb),
    /// A mirror-smooth conductor of complex index eta + i k.
    SmoothConductor { eta: Rgb, k: Rgb },
    /// A GGX conductor.
    RoughConductor(RoughConductor),
}

impl Base {
    pub(super) fn is_specular(&self) -> bool {
        matches!(self, Base::SmoothConductor { .. })
    }

    /// f(wo, wi); zero for a smooth conductor and for directions on opposite sides.
    pub(super) fn f(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z * wi.z <= 0.0 {
            return Rgb::ZERO;
        }
        match self {
            Base::Diffuse(r) => *r * INV_PI,
            Base::SmoothConductor { .. } => Rgb::ZERO,
            Base::RoughConductor(b) => b.eval(wo, wi),
        }
    }

    /// The density with which `sample` gives `wi`.
    pub(super) fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z * wi.z <= 0.0 {
            return 0.0;
        }
        match self {
            Base::Diffuse(_) => warp::cosine_hemisphere_pdf(wi.abs()),
            Base::SmoothConductor { .. } => 0.0,
            Base::RoughConductor(b) => b.pdf(wo, wi),
        }
    }

    /// Samples a reflected direction for `wo`.
    pub(super) fn sample(&self, wo: Vec3, u: Vec2) -> Option<Scatter> {
        match self {
            Base::Diffuse(r) => {
                let wi = warp::square_to_cosine_hemisphere(u);
                let wi = Vec3::new(wi.x, wi.y, wi.z.copysign(wo.z));
                Some(Scatter {
                    wi,
                    f: *r * INV_PI,
                    pdf: warp::cosine_hemisphere_pdf(wi.abs()),
                    specular: false,
                })
            }
            Base::SmoothConductor { eta, k } => {
                let wi = reflect_z(wo);
                Some(Scatter {
                    wi,
                    f: fresnel::conductor(wi.z, *eta, *k) / wi.z.abs(),
                    pdf: 1.0,
                    specular: true,
                })
            }
            Base::RoughConductor(b) => b.scatter(wo, u),
        }
        .filter(Scatter::carries_light)
    }
}
