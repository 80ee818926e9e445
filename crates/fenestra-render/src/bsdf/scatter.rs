//! One scattering event in pbrt-v4's terms, for BSDFs built out of others (the layered coats):
//! the value of f rather than the path weight, which direction light travels, and which lobes
//! may be sampled.

use fenestra_core::{Rgb, Vec3};

/// A sampled direction with f (without the cosine; for a Dirac lobe its weight over
/// |cos wi|) and the density (for a Dirac lobe, the chosen lobe's probability).
#[derive(Clone, Copy, Debug)]
pub struct Scatter {
    /// The sampled direction (local frame).
    pub wi: Vec3,
    /// f(wo, wi).
    pub f: Rgb,
    /// The density of `wi`.
    pub pdf: f32,
    /// From a Dirac lobe.
    pub specular: bool,
}

impl Scatter {
    /// f |cos wi| / pdf.
    pub fn weight(&self) -> Rgb {
        self.f * (self.wi.z.abs() / self.pdf)
    }

    /// Whether it carries light: a positive density, a direction off the surface, some f.
    pub fn carries_light(&self) -> bool {
        self.pdf > 0.0 && self.wi.z != 0.0 && self.f.max_component() > 0.0
    }
}

/// Which quantity a path carries: radiance (traced from the camera) or importance (traced
/// from a light). Refraction scales radiance by 1/eta^2 and leaves importance unscaled
/// (Veach 1997 §5.2), so a BTDF evaluated for the other direction of travel differs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Camera paths.
    Radiance,
    /// Light paths (the adjoint).
    Importance,
}

/// Which lobes of an interface a sample may take.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lobes {
    /// Reflection only.
    Reflection,
    /// Transmission only.
    Transmission,
    /// Both, each with its Fresnel share.
    All,
}

impl Lobes {
    /// The probabilities of reflecting and of transmitting given Fresnel reflectance `r`,
    /// or `None` if neither lobe may be taken.
    pub fn shares(self, r: f32) -> Option<(f32, f32)> {
        let (pr, pt) = match self {
            Lobes::Reflection => (r, 0.0),
            Lobes::Transmission => (0.0, 1.0 - r),
            Lobes::All => (r, 1.0 - r),
        };
        (pr + pt > 0.0).then(|| (pr / (pr + pt), pt / (pr + pt)))
    }
}
