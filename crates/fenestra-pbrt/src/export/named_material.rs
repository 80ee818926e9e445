//! A scene's materials as pbrt-v4's named materials: each of fenestra's materials as the
//! pbrt-v4 material it was read from (or, for glTF's, its nearest: `metallic_roughness`).

use super::{metallic_roughness, rgb};
use fenestra_scene::material::{self, Material};
use std::fmt::Write as _;

pub(super) fn material(s: &mut String, i: usize, m: &Material) {
    let _ = write!(s, "MakeNamedMaterial \"m{i}\" ");
    match m {
        Material::Diffuse(material::Diffuse { reflectance }) => {
            let _ = write!(
                s,
                "\"string type\" \"diffuse\" \"rgb reflectance\" [ {} ]",
                rgb(*reflectance)
            );
        }
        Material::TexturedDiffuse(material::TexturedDiffuse { .. }) => {
            let _ = write!(
                s,
                "\"string type\" \"diffuse\" \"texture reflectance\" \"t{i}\""
            );
        }
        Material::Mirror(material::Mirror { reflectance }) => {
            let _ = write!(
                s,
                "\"string type\" \"conductor\" \"rgb reflectance\" [ {} ]",
                rgb(*reflectance)
            );
        }
        Material::Dielectric(material::Dielectric { eta }) => {
            let _ = write!(s, "\"string type\" \"dielectric\" \"float eta\" [ {eta} ]");
        }
        Material::ThinDielectric(material::ThinDielectric { eta }) => {
            let _ = write!(
                s,
                "\"string type\" \"thindielectric\" \"float eta\" [ {eta} ]"
            );
        }
        Material::Phong(material::Phong {
            diffuse,
            specular,
            exponent,
        }) => {
            let _ = write!(
                s,
                "\"string type\" \"phong\" \"rgb diffuse\" [ {} ] \"rgb specular\" [ {} ] \"float exponent\" [ {exponent} ]",
                rgb(*diffuse),
                rgb(*specular)
            );
        }
        Material::Ward(material::Ward {
            diffuse,
            specular,
            alpha_x,
            alpha_y,
        }) => {
            let _ = write!(
                s,
                "\"string type\" \"ward\" \"rgb diffuse\" [ {} ] \"rgb specular\" [ {} ] \"float alphax\" [ {alpha_x} ] \"float alphay\" [ {alpha_y} ]",
                rgb(*diffuse),
                rgb(*specular)
            );
        }
        Material::RoughConductor(material::RoughConductor {
            eta,
            k,
            alpha_x,
            alpha_y,
            roughness,
        }) => {
            // A texture is written with its remapping; constants are alphas, so under
            // remapping they are written squared.
            let remap = roughness.as_ref().is_some_and(|r| r.remap);
            let (tu, tv) = roughness
                .as_ref()
                .map_or((false, false), |r| (r.u.is_some(), r.v.is_some()));
            let axis = |name: &str, textured: bool, alpha: f32| {
                if textured {
                    format!("\"texture {name}roughness\" \"r{i}{name}\"")
                } else if remap {
                    format!("\"float {name}roughness\" [ {} ]", alpha * alpha)
                } else {
                    format!("\"float {name}roughness\" [ {alpha} ]")
                }
            };
            let _ = write!(
                s,
                "\"string type\" \"conductor\" \"rgb eta\" [ {} ] \"rgb k\" [ {} ] {} {} \"bool remaproughness\" {remap}",
                rgb(*eta),
                rgb(*k),
                axis("u", tu, *alpha_x),
                axis("v", tv, *alpha_y),
            );
        }
        Material::RoughDielectric(material::RoughDielectric { eta, alpha }) => {
            let _ = write!(
                s,
                "\"string type\" \"dielectric\" \"float eta\" [ {eta} ] \"float roughness\" [ {alpha} ] \"bool remaproughness\" false"
            );
        }
        Material::CoatedConductor(material::CoatedConductor {
            interface_eta,
            interface_alpha,
            eta,
            k,
            alpha_x,
            alpha_y,
            layers,
        }) => {
            let _ = write!(
                s,
                "\"string type\" \"coatedconductor\" \"float interface.eta\" [ {interface_eta} ] \"float interface.roughness\" [ {interface_alpha} ] \"rgb conductor.eta\" [ {} ] \"rgb conductor.k\" [ {} ] \"float conductor.uroughness\" [ {alpha_x} ] \"float conductor.vroughness\" [ {alpha_y} ] \"bool remaproughness\" false{}",
                rgb(*eta),
                rgb(*k),
                layer_parameters(layers)
            );
        }
        Material::DiffuseTransmission(material::DiffuseTransmission {
            reflectance,
            transmittance,
        }) => {
            let _ = write!(
                s,
                "\"string type\" \"diffusetransmission\" \"rgb reflectance\" [ {} ] \"rgb transmittance\" [ {} ]",
                rgb(*reflectance),
                rgb(*transmittance)
            );
        }
        Material::Mix(material::Mix {
            materials: [a, b],
            amount,
        }) => {
            let _ = write!(
                s,
                "\"string type\" \"mix\" \"string materials\" [ \"m{a}\" \"m{b}\" ] \"float amount\" [ {amount} ]"
            );
        }
        Material::MetallicRoughness(m) => {
            s.push_str(&metallic_roughness::parameters(i, m));
        }
        Material::CoatedDiffuse(material::CoatedDiffuse {
            reflectance,
            texture,
            eta,
            alpha,
            layers,
        }) => {
            let reflectance = match texture {
                Some(_) => format!("\"texture reflectance\" \"t{i}\""),
                None => format!("\"rgb reflectance\" [ {} ]", rgb(*reflectance)),
            };
            let _ = write!(
                s,
                "\"string type\" \"coateddiffuse\" {reflectance} \"float eta\" [ {eta} ] \"float roughness\" [ {alpha} ] \"bool remaproughness\" false{}",
                layer_parameters(layers)
            );
        }
    }
    s.push('\n');
}

/// A coated material's slab as pbrt-v4's parameters (a leading space each).
fn layer_parameters(l: &material::Layers) -> String {
    format!(
        " \"float thickness\" [ {} ] \"rgb albedo\" [ {} ] \"float g\" [ {} ] \"integer maxdepth\" [ {} ] \"integer nsamples\" [ {} ]",
        l.thickness,
        rgb(l.albedo),
        l.g,
        l.max_depth,
        l.samples
    )
}
