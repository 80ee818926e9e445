//! Materials as parameters; the render crate's bsdf module evaluates and samples them.

use crate::texture::{ImageTexture, RoughnessTexture};
use fenestra_core::sampler::hash_combine;
use fenestra_core::{Rgb, Vec3};
use std::sync::Arc;

/// A surface's scattering, as parameters.
#[derive(Clone, Debug)]
pub enum Material {
    /// Lambertian reflector.
    Diffuse {
        /// Albedo.
        reflectance: Rgb,
    },
    /// Lambertian reflector whose reflectance comes from an image texture.
    TexturedDiffuse {
        /// The albedo texture, looked up at the surface's uv.
        texture: Arc<ImageTexture>,
    },
    /// Perfect specular reflector.
    Mirror {
        /// Reflectance.
        reflectance: Rgb,
    },
    /// Smooth dielectric interface with Fresnel reflection and refraction (seed 000 §2.4).
    Dielectric {
        /// Interior index of refraction over the exterior one.
        eta: f32,
    },
    /// A thin dielectric sheet (a window pane): specular reflection with the sheet's total
    /// reflectance including inter-reflections, straight transmission of the rest.
    ThinDielectric {
        /// The sheet's index of refraction.
        eta: f32,
    },
    /// Energy-normalised Phong: kd/pi + ks (n+2)/(2 pi) cos^n(alpha).
    Phong {
        /// kd.
        diffuse: Rgb,
        /// ks.
        specular: Rgb,
        /// The lobe exponent n.
        exponent: f32,
    },
    /// Anisotropic Ward with Walter's (2005) normalisation (seed 003 §2.5).
    Ward {
        /// Diffuse albedo.
        diffuse: Rgb,
        /// Specular albedo.
        specular: Rgb,
        /// Roughness along the tangent.
        alpha_x: f32,
        /// Roughness along the bitangent.
        alpha_y: f32,
    },
    /// GGX microfacet conductor with complex index eta + i k per channel.
    RoughConductor {
        /// Real part of the index of refraction.
        eta: Rgb,
        /// Absorption coefficient (imaginary part).
        k: Rgb,
        /// GGX roughness along the tangent.
        alpha_x: f32,
        /// GGX roughness along the bitangent.
        alpha_y: f32,
        /// Roughness varying over the surface, overriding `alpha_x`/`alpha_y` where given
        /// (those then hold its mean).
        roughness: Option<Arc<RoughnessTexture>>,
    },
    /// GGX microfacet dielectric (Walter et al. 2007).
    RoughDielectric {
        /// Interior index of refraction over the exterior one.
        eta: f32,
        /// GGX roughness.
        alpha: f32,
    },
    /// pbrt-v4's coatedconductor: a GGX conductor under a GGX dielectric interface.
    CoatedConductor {
        /// The interface's index of refraction.
        interface_eta: f32,
        /// The interface's GGX roughness.
        interface_alpha: f32,
        /// The conductor's index of refraction.
        eta: Rgb,
        /// The conductor's absorption coefficient.
        k: Rgb,
        /// The conductor's GGX roughness along the tangent.
        alpha_x: f32,
        /// The conductor's GGX roughness along the bitangent.
        alpha_y: f32,
    },
    /// pbrt-v4's diffusetransmission: Lambertian reflection on the side light comes from and
    /// Lambertian transmission to the other (leaves, lampshades, paper).
    DiffuseTransmission {
        /// Albedo of the reflection.
        reflectance: Rgb,
        /// Albedo of the transmission.
        transmittance: Rgb,
    },
    /// pbrt-v4's mix: at each surface point one of two earlier materials, the second with
    /// probability `amount`, chosen by a hash of the point (so a point always gets the same).
    Mix {
        /// Indices of the two materials; both below this material's own index.
        materials: [usize; 2],
        /// Probability of the second material, in [0, 1].
        amount: f32,
    },
    /// pbrt-v4's coateddiffuse: a Lambertian base under a GGX dielectric interface.
    CoatedDiffuse {
        /// The base's albedo (the texture's mean when it has one).
        reflectance: Rgb,
        /// The base's albedo varying over the surface, looked up at each hit.
        texture: Option<Arc<ImageTexture>>,
        /// The interface's index of refraction.
        eta: f32,
        /// The interface's GGX roughness.
        alpha: f32,
    },
}

impl Material {
    /// A grey Lambertian material of albedo `r`.
    pub fn diffuse(r: f32) -> Self {
        Material::Diffuse {
            reflectance: Rgb::splat(r),
        }
    }

    /// The image texture the material looks up at each hit, if any.
    pub fn texture(&self) -> Option<&Arc<ImageTexture>> {
        match self {
            Material::TexturedDiffuse { texture } => Some(texture),
            Material::CoatedDiffuse { texture, .. } => texture.as_ref(),
            _ => None,
        }
    }

    /// Which material a [`Material::Mix`] is at the point `p` (any other material is itself):
    /// the second with probability `amount`, by a hash of `p`'s coordinates, followed through
    /// mixes of mixes. `materials[index]` must have passed [`Scene`](crate::Scene)'s checks.
    pub fn resolve(materials: &[Material], mut index: usize, p: Vec3) -> usize {
        let h = p
            .to_array()
            .iter()
            .fold(0x6d69_7865, |h, c| hash_combine(h, c.to_bits()));
        while let Material::Mix {
            materials: pair,
            amount,
        } = materials[index]
        {
            // 24 bits of the hash as a uniform number in [0, 1); a fresh hash per level.
            let u = (hash_combine(h, index as u32) >> 8) as f32 / (1u32 << 24) as f32;
            index = pair[usize::from(u < amount)];
        }
        index
    }

    /// A parameter that makes no physical sense, as a message; `None` when valid.
    pub fn validate(&self) -> Option<String> {
        let rgb_ok = |c: &Rgb| c.is_finite() && c.r >= 0.0 && c.g >= 0.0 && c.b >= 0.0;
        let alpha_ok = |a: f32| a.is_finite() && a > 0.0;
        match self {
            Material::Diffuse { reflectance: r } | Material::Mirror { reflectance: r } => {
                (!rgb_ok(r) || r.max_component() > 1.0)
                    .then(|| format!("reflectance {r:?} must lie in [0, 1]"))
            }
            Material::Dielectric { eta }
            | Material::ThinDielectric { eta }
            | Material::RoughDielectric { eta, .. }
                if !(eta.is_finite() && *eta > 0.0) =>
            {
                Some(format!("index of refraction {eta} must be positive"))
            }
            Material::DiffuseTransmission {
                reflectance,
                transmittance,
            } => [
                ("reflectance", reflectance),
                ("transmittance", transmittance),
            ]
            .into_iter()
            .find(|(_, c)| !rgb_ok(c) || c.max_component() > 1.0)
            .map(|(what, c)| format!("{what} {c:?} must lie in [0, 1]")),
            Material::Mix { amount, .. } => (!(0.0..=1.0).contains(amount))
                .then(|| format!("mix amount {amount} must lie in [0, 1]")),
            Material::CoatedDiffuse {
                reflectance,
                eta,
                alpha,
                ..
            } => {
                if !rgb_ok(reflectance) || reflectance.max_component() > 1.0 {
                    Some(format!("reflectance {reflectance:?} must lie in [0, 1]"))
                } else if !(eta.is_finite() && *eta > 0.0) {
                    Some(format!("index of refraction {eta} must be positive"))
                } else {
                    (!alpha_ok(*alpha)).then(|| format!("roughness {alpha} must be positive"))
                }
            }
            Material::CoatedConductor {
                interface_eta,
                interface_alpha,
                eta,
                k,
                alpha_x,
                alpha_y,
            } => {
                if !rgb_ok(eta) || !rgb_ok(k) {
                    Some("conductor eta and k must be finite and non-negative".into())
                } else if !(interface_eta.is_finite() && *interface_eta > 0.0) {
                    Some(format!(
                        "index of refraction {interface_eta} must be positive"
                    ))
                } else {
                    (![*interface_alpha, *alpha_x, *alpha_y]
                        .into_iter()
                        .all(alpha_ok))
                    .then(|| "roughness must be positive".into())
                }
            }
            Material::RoughDielectric { alpha, .. } if !alpha_ok(*alpha) => {
                Some(format!("roughness {alpha} must be positive"))
            }
            Material::Phong {
                diffuse,
                specular,
                exponent,
            } => {
                if !rgb_ok(diffuse) || !rgb_ok(specular) {
                    Some("Phong reflectances must be finite and non-negative".into())
                } else {
                    (!(exponent.is_finite() && *exponent >= 0.0))
                        .then(|| format!("Phong exponent {exponent} must be >= 0"))
                }
            }
            Material::Ward {
                diffuse,
                specular,
                alpha_x,
                alpha_y,
            } => {
                if !rgb_ok(diffuse) || !rgb_ok(specular) {
                    Some("Ward reflectances must be finite and non-negative".into())
                } else {
                    (!alpha_ok(*alpha_x) || !alpha_ok(*alpha_y))
                        .then(|| "Ward roughness must be positive".into())
                }
            }
            Material::RoughConductor {
                eta,
                k,
                alpha_x,
                alpha_y,
                ..
            } => {
                if !rgb_ok(eta) || !rgb_ok(k) {
                    Some("conductor eta and k must be finite and non-negative".into())
                } else {
                    (!alpha_ok(*alpha_x) || !alpha_ok(*alpha_y))
                        .then(|| "conductor roughness must be positive".into())
                }
            }
            _ => None,
        }
    }
}
