//! The dielectric interface on top of a layered material, seen from outside or from inside
//! the slab: smooth (a Dirac pair of lobes) or GGX-rough.

use super::super::scatter::{Lobes, Mode, Scatter};
use super::super::{RoughDielectric, SmoothDielectric};
use fenestra_core::{Vec2, Vec3};
use fenestra_scene::material::SMOOTH_ALPHA;

/// A coat of index `eta` over the slab (the slab is the -z side).
#[derive(Clone, Debug)]
pub(super) enum Coat {
    /// Mirror reflection and refraction only.
    Smooth(SmoothDielectric),
    /// GGX microfacets.
    Rough(RoughDielectric),
}

impl Coat {
    /// pbrt-v4's rule: an interface of index 1, or of roughness below [`SMOOTH_ALPHA`], is smooth.
    pub(super) fn new(eta: f32, alpha: f32) -> Self {
        if eta == 1.0 || alpha <= SMOOTH_ALPHA {
            Coat::Smooth(SmoothDielectric { eta })
        } else {
            Coat::Rough(RoughDielectric::new(eta, alpha))
        }
    }

    pub(super) fn is_specular(&self) -> bool {
        matches!(self, Coat::Smooth(_))
    }

    /// f(wo, wi), zero for a smooth coat.
    pub(super) fn f(&self, wo: Vec3, wi: Vec3, mode: Mode) -> f32 {
        match self {
            Coat::Smooth(_) => 0.0,
            Coat::Rough(b) => b.f(wo, wi, mode),
        }
    }

    /// The density of `wi` when sampling `lobes` for `wo`, zero for a smooth coat.
    pub(super) fn pdf(&self, wo: Vec3, wi: Vec3, lobes: Lobes) -> f32 {
        match self {
            Coat::Smooth(_) => 0.0,
            Coat::Rough(b) => b.pdf_of(wo, wi, lobes),
        }
    }

    /// Samples one of `lobes` for `wo` (either side).
    pub(super) fn sample(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: Mode,
        lobes: Lobes,
    ) -> Option<Scatter> {
        match self {
            Coat::Smooth(b) => b.scatter(wo, uc, mode, lobes),
            Coat::Rough(b) => b.scatter(wo, uc, u, mode, lobes),
        }
        .filter(Scatter::carries_light)
    }
}
