//! Scattering functions in a local shading frame (normal along +z). Opaque materials are
//! two-sided: they reflect on whichever side `wo` lies. `sample` returns the weight
//! f * |cos| / pdf that a path's throughput is multiplied by.

mod conductor;
mod dielectric;
mod diffuse;
pub mod fresnel;
mod layered;
mod metallic_roughness;
pub(crate) mod microfacet;
mod mirror;
mod phong;
mod rough_dielectric;
mod scatter;
mod specular_albedo;
mod ward;

pub use conductor::RoughConductor;
pub use dielectric::{SmoothDielectric, ThinDielectric};
pub use diffuse::{Diffuse, DiffuseTransmission};
pub use layered::Layered;
pub use metallic_roughness::MetallicRoughness;
pub use mirror::Mirror;
pub use phong::Phong;
pub use rough_dielectric::RoughDielectric;
pub use ward::Ward;

use fenestra_core::{Rgb, Vec2, Vec3};
use fenestra_scene::Material;

/// A direction sampled by a BSDF.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// Sampled incident direction (local frame).
    pub wi: Vec3,
    /// f * |cos theta_i| / pdf.
    pub weight: Rgb,
    /// Solid-angle density; for delta lobes the discrete probability of the chosen lobe.
    pub pdf: f32,
    /// From a Dirac lobe (mirror, smooth glass): no MIS, no light sampling.
    pub delta: bool,
}

impl BsdfSample {
    /// A sampled reflection direction `wi` (upper hemisphere) of a non-delta lobe, with its
    /// weight and density from the material's own `eval` and `pdf` (which include every lobe
    /// of a mixture); `None` below the surface.
    fn reflected(
        wi: Vec3,
        eval: impl Fn(Vec3) -> Rgb,
        pdf: impl Fn(Vec3) -> f32,
    ) -> Option<BsdfSample> {
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = pdf(wi);
        (pdf > 0.0).then(|| BsdfSample {
            wi,
            weight: eval(wi) * (wi.z / pdf),
            pdf,
            delta: false,
        })
    }
}

/// A material's scattering, ready to evaluate and sample.
#[derive(Clone, Debug)]
pub enum Bsdf {
    /// Lambertian.
    Diffuse(Diffuse),
    /// Perfect mirror.
    Mirror(Mirror),
    /// Smooth glass.
    SmoothDielectric(SmoothDielectric),
    /// A thin glass pane.
    ThinDielectric(ThinDielectric),
    /// Energy-normalised Phong.
    Phong(Phong),
    /// Anisotropic Ward.
    Ward(Ward),
    /// GGX conductor.
    RoughConductor(RoughConductor),
    /// GGX dielectric.
    RoughDielectric(RoughDielectric),
    /// Lambertian reflection and transmission.
    DiffuseTransmission(DiffuseTransmission),
    /// pbrt-v4's coated materials: a dielectric coat over a Lambertian or conductor base,
    /// simulated by random walks.
    Layered(Layered),
    /// glTF's metallic-roughness BRDF.
    MetallicRoughness(MetallicRoughness),
}

/// Mirror image of `v` in the local z axis' plane (reflection about the normal).
pub fn reflect_z(v: Vec3) -> Vec3 {
    Vec3::new(-v.x, -v.y, v.z)
}

/// Reflection of `wo` about the unit vector `h`.
pub fn reflect(wo: Vec3, h: Vec3) -> Vec3 {
    2.0 * wo.dot(h) * h - wo
}

impl Bsdf {
    /// The BSDF of material `m` (textured materials get their texture's mean; see
    /// `RenderScene::bsdf_at`). A mix has none of its own: `RenderScene` resolves it to one of
    /// its materials at each point; alone, it absorbs.
    pub fn from_material(m: &Material) -> Bsdf {
        match m {
            Material::Mix(_) => Bsdf::Diffuse(Diffuse {
                reflectance: Rgb::ZERO,
            }),
            Material::Diffuse(m) => Bsdf::Diffuse(m.into()),
            Material::TexturedDiffuse(m) => Bsdf::Diffuse(m.into()),
            Material::DiffuseTransmission(m) => Bsdf::DiffuseTransmission(m.into()),
            Material::Mirror(m) => Bsdf::Mirror(m.into()),
            Material::Dielectric(m) => Bsdf::SmoothDielectric(m.into()),
            Material::ThinDielectric(m) => Bsdf::ThinDielectric(m.into()),
            Material::RoughDielectric(m) => Bsdf::RoughDielectric(m.into()),
            Material::Phong(m) => Bsdf::Phong(m.into()),
            Material::Ward(m) => Bsdf::Ward(m.into()),
            Material::RoughConductor(m) => Bsdf::RoughConductor(m.into()),
            Material::CoatedDiffuse(m) => Bsdf::Layered(m.into()),
            Material::CoatedConductor(m) => Bsdf::Layered(m.into()),
            Material::MetallicRoughness(m) => Bsdf::MetallicRoughness(m.into()),
        }
    }

    /// A Lambertian lobe plus a glossy one (Phong, Ward) as its Lambertian albedo and the
    /// glossy lobe alone, for caches that treat the two apart (f = albedo / pi + the lobe's
    /// f); `None` for other BSDFs and for glossy lobes without a Lambertian part.
    pub fn lambertian_split(&self) -> Option<(Rgb, Bsdf)> {
        let (albedo, glossy) = match self {
            Bsdf::Phong(b) => {
                let (albedo, lobe) = b.split();
                (albedo, Bsdf::Phong(lobe))
            }
            Bsdf::Ward(b) => {
                let (albedo, lobe) = b.split();
                (albedo, Bsdf::Ward(lobe))
            }
            _ => return None,
        };
        (albedo.max_component() > 0.0).then_some((albedo, glossy))
    }

    /// Whether the BSDF may depend on the direction of the surface's tangent (anisotropic
    /// lobes): the others look the same in any frame around the normal.
    pub fn needs_tangent(&self) -> bool {
        match self {
            Bsdf::Layered(b) => b.needs_tangent(),
            _ => matches!(self, Bsdf::Ward(_) | Bsdf::RoughConductor(_)),
        }
    }

    /// Whether every lobe is a Dirac delta (light sampling is pointless there).
    pub fn is_delta(&self) -> bool {
        match self {
            Bsdf::Layered(b) => b.is_delta(),
            _ => matches!(
                self,
                Bsdf::Mirror(_) | Bsdf::SmoothDielectric(_) | Bsdf::ThinDielectric(_)
            ),
        }
    }

    /// Whether the material transmits (otherwise it is opaque and two-sided).
    pub fn is_transmissive(&self) -> bool {
        matches!(
            self,
            Bsdf::SmoothDielectric(_)
                | Bsdf::ThinDielectric(_)
                | Bsdf::RoughDielectric(_)
                | Bsdf::DiffuseTransmission(_)
        )
    }

    /// What a sample drawn for `wo` towards `wi` (local directions) must be multiplied by when
    /// it carries light from `wo`'s side rather than radiance towards it (light paths, the
    /// adjoint of camera paths): refraction through a dielectric interface compresses
    /// radiance by 1/eta'^2 and leaves importance unscaled (Veach 1997 §5.2), so eta'^2 where
    /// the sample crosses such an interface, 1 otherwise (panes come back into the medium
    /// they left).
    pub fn importance_scale(&self, wo: Vec3, wi: Vec3) -> f32 {
        let eta = match self {
            Bsdf::SmoothDielectric(b) => b.eta,
            Bsdf::RoughDielectric(b) => b.eta(),
            _ => return 1.0,
        };
        if wo.z * wi.z >= 0.0 {
            return 1.0;
        }
        let etap = if wo.z > 0.0 { eta } else { 1.0 / eta };
        etap * etap
    }

    /// BSDF value f(wo, wi) (without the cosine).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        match self {
            Bsdf::RoughDielectric(b) => return b.eval(wo, wi),
            Bsdf::DiffuseTransmission(b) => return b.eval(wo, wi),
            _ => {}
        }
        let Some((wo, wi)) = opaque_side(wo, wi) else {
            return Rgb::ZERO;
        };
        match self {
            Bsdf::Diffuse(b) => b.eval(wo, wi),
            Bsdf::Phong(b) => b.eval(wo, wi),
            Bsdf::Ward(b) => b.eval(wo, wi),
            Bsdf::RoughConductor(b) => b.eval(wo, wi),
            Bsdf::Layered(b) => b.eval(wo, wi),
            Bsdf::MetallicRoughness(b) => b.eval(wo, wi),
            Bsdf::Mirror(_)
            | Bsdf::SmoothDielectric(_)
            | Bsdf::ThinDielectric(_)
            | Bsdf::RoughDielectric(_)
            | Bsdf::DiffuseTransmission(_) => Rgb::ZERO,
        }
    }

    /// Solid-angle density of `sample` producing `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Bsdf::RoughDielectric(b) => return b.pdf(wo, wi),
            Bsdf::DiffuseTransmission(b) => return b.pdf(wo, wi),
            _ => {}
        }
        let Some((wo, wi)) = opaque_side(wo, wi) else {
            return 0.0;
        };
        match self {
            Bsdf::Diffuse(b) => b.pdf(wo, wi),
            Bsdf::Phong(b) => b.pdf(wo, wi),
            Bsdf::Ward(b) => b.pdf(wo, wi),
            Bsdf::RoughConductor(b) => b.pdf(wo, wi),
            Bsdf::Layered(b) => b.pdf(wo, wi),
            Bsdf::MetallicRoughness(b) => b.pdf(wo, wi),
            Bsdf::Mirror(_)
            | Bsdf::SmoothDielectric(_)
            | Bsdf::ThinDielectric(_)
            | Bsdf::RoughDielectric(_)
            | Bsdf::DiffuseTransmission(_) => 0.0,
        }
    }

    /// [`Bsdf::pdf`] where two sampling strategies must agree on it exactly (the densities in
    /// an MIS weight that a camera path and a light path compute for the same path): the
    /// density itself, but for a layered BSDF, whose density is a random-walk estimate seeded
    /// by the directions' bits, a deterministic stand-in ([`Layered::mis_pdf`]).
    pub fn mis_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Bsdf::Layered(b) => opaque_side(wo, wi).map_or(0.0, |(wo, wi)| b.mis_pdf(wo, wi)),
            _ => self.pdf(wo, wi),
        }
    }

    /// Samples an incident direction; `uc` picks a lobe, `u` places the direction.
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        match self {
            Bsdf::SmoothDielectric(b) => return b.sample(wo, uc),
            Bsdf::ThinDielectric(b) => return b.sample(wo, uc),
            Bsdf::RoughDielectric(b) => return b.sample(wo, uc, u),
            Bsdf::DiffuseTransmission(b) => return b.sample(wo, uc, u),
            _ => {}
        }
        let flip = wo.z < 0.0;
        let wo = if flip { flip_z(wo) } else { wo };
        let s = match self {
            Bsdf::Diffuse(b) => b.sample(wo, u),
            Bsdf::Mirror(b) => b.sample(wo),
            Bsdf::Phong(b) => b.sample(wo, uc, u),
            Bsdf::Ward(b) => b.sample(wo, uc, u),
            Bsdf::RoughConductor(b) => b.sample(wo, u),
            Bsdf::Layered(b) => b.sample(wo, uc, u),
            Bsdf::MetallicRoughness(b) => b.sample(wo, uc, u),
            Bsdf::SmoothDielectric(_)
            | Bsdf::ThinDielectric(_)
            | Bsdf::RoughDielectric(_)
            | Bsdf::DiffuseTransmission(_) => None,
        }?;
        let ok = s.wi.z > 0.0 && s.pdf > 0.0 && s.weight.is_finite();
        ok.then(|| BsdfSample {
            wi: if flip { flip_z(s.wi) } else { s.wi },
            ..s
        })
    }
}

fn flip_z(v: Vec3) -> Vec3 {
    Vec3::new(v.x, v.y, -v.z)
}

/// For opaque two-sided materials: both directions moved to the upper hemisphere, or `None`
/// when they lie on opposite sides (no transmission).
fn opaque_side(wo: Vec3, wi: Vec3) -> Option<(Vec3, Vec3)> {
    if wo.z * wi.z <= 0.0 {
        None
    } else if wo.z < 0.0 {
        Some((flip_z(wo), flip_z(wi)))
    } else {
        Some((wo, wi))
    }
}

/// Probability of choosing the specular lobe of a diffuse + specular mixture.
fn specular_probability(diffuse: Rgb, specular: Rgb) -> f32 {
    let (d, s) = (diffuse.average(), specular.average());
    if d + s <= 0.0 {
        0.0
    } else {
        s / (d + s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lambertian_split_adds_up_to_the_bsdf() {
        let (kd, ks) = (Rgb::new(0.3, 0.2, 0.1), Rgb::splat(0.5));
        for bsdf in [
            Bsdf::Phong(Phong::new(kd, ks, 20.0)),
            Bsdf::Ward(Ward::new(kd, ks, 0.1, 0.3)),
        ] {
            let (albedo, lobe) = bsdf.lambertian_split().expect("split");
            assert_eq!(albedo, kd);
            assert!(
                lobe.lambertian_split().is_none(),
                "the lobe has no Lambertian part"
            );
            let wo = Vec3::new(0.3, -0.2, 0.93).normalize();
            for wi in [
                Vec3::new(-0.3, 0.2, 0.93).normalize(),
                Vec3::new(0.5, 0.5, 0.7).normalize(),
                Vec3::new(-0.8, 0.1, 0.2).normalize(),
            ] {
                let whole = bsdf.eval(wo, wi);
                let parts = albedo * std::f32::consts::FRAC_1_PI + lobe.eval(wo, wi);
                assert!((whole - parts).max_component().abs() < 1e-5 * whole.max_component());
                assert!((parts - whole).max_component().abs() < 1e-5 * whole.max_component());
            }
        }
        assert!(Bsdf::Phong(Phong::new(Rgb::ZERO, ks, 5.0))
            .lambertian_split()
            .is_none());
    }
}
