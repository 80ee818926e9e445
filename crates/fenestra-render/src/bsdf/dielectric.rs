//! Smooth dielectric interface: Fresnel-weighted choice between mirror reflection and
//! refraction, total internal reflection included (seed 000 §2.4).

use super::scatter::{Lobes, Mode, Scatter};
use super::{fresnel, reflect_z, BsdfSample};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::material;

/// A smooth dielectric interface: Fresnel reflection and refraction (seed 000 §2.4).
#[derive(Clone, Debug)]
pub struct SmoothDielectric {
    /// Interior index over exterior index; the exterior is the +z side.
    pub eta: f32,
}

impl SmoothDielectric {
    /// Samples an incident direction for `wo`.
    pub fn sample(&self, wo: Vec3, uc: f32) -> Option<BsdfSample> {
        let s = self.scatter(wo, uc, Mode::Radiance, Lobes::All)?;
        Some(BsdfSample {
            wi: s.wi,
            weight: s.weight(),
            pdf: s.pdf,
            delta: true,
        })
    }

    /// The refracted direction for `wo` and the share of radiance it carries, (1 - R) / eta'^2
    /// (what a camera path that chose refraction keeps of its Fresnel share), or `None` under
    /// total internal reflection: light followed through the interface deterministically.
    pub fn transmit(&self, wo: Vec3) -> Option<(Vec3, f32)> {
        let s = self.scatter(wo, 0.5, Mode::Radiance, Lobes::Transmission)?;
        Some((s.wi, s.weight().max_component()))
    }

    /// Samples one of `lobes` for `wo`: the mirror direction or the refracted one, in
    /// proportion to their Fresnel shares.
    pub(super) fn scatter(&self, wo: Vec3, uc: f32, mode: Mode, lobes: Lobes) -> Option<Scatter> {
        let r = fresnel::dielectric(wo.z, self.eta);
        let (pr, pt) = lobes.shares(r)?;
        let (wi, f, pdf) = if uc < pr {
            let wi = reflect_z(wo);
            (wi, r / wi.z.abs(), pr)
        } else {
            let (wi, etap) = fresnel::refract(wo, Vec3::Z, self.eta)?;
            // Radiance is compressed by eta^2 when it enters a denser medium (non-symmetric
            // scattering for camera paths, Veach 1997 §5.2).
            let scale = match mode {
                Mode::Radiance => 1.0 / (etap * etap),
                Mode::Importance => 1.0,
            };
            (wi, (1.0 - r) * scale / wi.z.abs(), pt)
        };
        (pdf > 0.0 && wi.z != 0.0).then_some(Scatter {
            wi,
            f: Rgb::splat(f),
            pdf,
            specular: true,
        })
    }
}

/// A thin dielectric sheet (pbrt's "thindielectric"): both interfaces of a pane in one
/// surface. The pane's reflectance sums the inter-reflections, R' = R + T^2 R / (1 - R^2);
/// the rest passes straight through, back into the medium it came from.
#[derive(Clone, Debug)]
pub struct ThinDielectric {
    /// The pane's index of refraction.
    pub eta: f32,
}

impl ThinDielectric {
    /// The pane's reflectance R' at incidence cosine `cos` (either side).
    pub fn reflectance(&self, cos: f32) -> f32 {
        let r = fresnel::dielectric(cos.abs(), self.eta);
        if r < 1.0 {
            let t = 1.0 - r;
            r + t * t * r / (1.0 - r * r)
        } else {
            r
        }
    }

    /// Samples an incident direction for `wo`.
    pub fn sample(&self, wo: Vec3, uc: f32) -> Option<BsdfSample> {
        let r = self.reflectance(wo.z);
        let (wi, pdf) = if uc < r {
            (reflect_z(wo), r)
        } else {
            (-wo, 1.0 - r)
        };
        (pdf > 0.0).then_some(BsdfSample {
            wi,
            weight: Rgb::ONE,
            pdf,
            delta: true,
        })
    }
}

impl From<&material::Dielectric> for SmoothDielectric {
    fn from(m: &material::Dielectric) -> Self {
        SmoothDielectric { eta: m.eta }
    }
}

impl From<&material::ThinDielectric> for ThinDielectric {
    fn from(m: &material::ThinDielectric) -> Self {
        ThinDielectric { eta: m.eta }
    }
}
