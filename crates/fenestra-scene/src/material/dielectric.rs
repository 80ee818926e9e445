//! Dielectric interfaces: smooth (seed 000 §2.4), thin sheets, and rough (GGX).

use super::checks::{index_of_refraction, roughness_ok};

/// Smooth dielectric interface with Fresnel reflection and refraction (seed 000 §2.4).
#[derive(Clone, Debug)]
pub struct Dielectric {
    /// Interior index of refraction over the exterior one.
    pub eta: f32,
}

impl Dielectric {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        index_of_refraction(self.eta)
    }
}

/// A thin dielectric sheet (a window pane): specular reflection with the sheet's total
/// reflectance including inter-reflections, straight transmission of the rest.
#[derive(Clone, Debug)]
pub struct ThinDielectric {
    /// The sheet's index of refraction.
    pub eta: f32,
}

impl ThinDielectric {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        index_of_refraction(self.eta)
    }
}

/// GGX microfacet dielectric (Walter et al. 2007).
#[derive(Clone, Debug)]
pub struct RoughDielectric {
    /// Interior index of refraction over the exterior one.
    pub eta: f32,
    /// GGX roughness.
    pub alpha: f32,
}

impl RoughDielectric {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        index_of_refraction(self.eta).or_else(|| {
            (!roughness_ok(self.alpha))
                .then(|| format!("roughness {} must be positive", self.alpha))
        })
    }
}
