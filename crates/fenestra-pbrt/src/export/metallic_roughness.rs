//! glTF's metallic-roughness material in pbrt-v4's terms. pbrt-v4 has no such material: the
//! dielectric part becomes a "diffuse" of the base colour (exact with no specular layer; with
//! one, its sheen is lost but not its energy: pbrt-v4's "coateddiffuse", a layer over the base,
//! kept a fifth of the light of a white room, docs/scenes.md), the metal a "conductor" of the
//! base colour's reflectance, the two a "mix" by the metallic factor.

use super::rgb;
use fenestra_scene::material::MetallicRoughness;

/// The parameters of material `m{i}`; the named materials they mix come from [`parts`].
pub(super) fn parameters(i: usize, m: &MetallicRoughness) -> String {
    match m.metallic {
        0.0 => dielectric(i, m),
        1.0 => metal(i, m),
        amount => format!(
            "\"string type\" \"mix\" \"string materials\" [ \"m{i}-dielectric\" \"m{i}-metal\" ] \"float amount\" [ {amount} ]"
        ),
    }
}

/// The named materials (name, parameters) that `parameters` mixes, to be written first.
pub(super) fn parts(i: usize, m: &MetallicRoughness) -> Vec<(String, String)> {
    if m.metallic == 0.0 || m.metallic == 1.0 {
        return Vec::new();
    }
    vec![
        (format!("m{i}-dielectric"), dielectric(i, m)),
        (format!("m{i}-metal"), metal(i, m)),
    ]
}

/// What the written material does not reproduce, one line each.
pub(super) fn approximations(i: usize, m: &MetallicRoughness) -> Vec<String> {
    let mut out = Vec::new();
    let mut say = |what: &str| out.push(format!("material m{i} (glTF metallic-roughness): {what}"));
    if m.metallic < 1.0 && m.specular > 0.0 {
        say("its dielectric part is a diffuse of the base colour (the specular sheen is left out)");
    }
    if m.metallic > 0.0 {
        say("its metal is a conductor of the base colour's reflectance (complex Fresnel, not Schlick)");
    }
    if m.base_color_texture.is_some() && m.base_color != fenestra_core::Rgb::ONE {
        say("the base colour factor under its texture is left out");
    }
    if m.metallic_roughness_texture.is_some() {
        say("the metallic-roughness texture is left out (its factors stand)");
    }
    if m.normal_map.is_some() {
        say("the normal map is left out");
    }
    if m.alpha.is_some() {
        say("its cut-out (alpha) is left out: the surface is solid");
    }
    if m.specular_color != fenestra_core::Rgb::ONE || !(m.specular == 0.0 || m.specular == 1.0) {
        say("the specular weight and colour are left out");
    }
    out
}

/// The base colour as a reflectance parameter: its texture `t{i}`, or the factor.
fn reflectance(i: usize, m: &MetallicRoughness) -> String {
    match m.base_color_texture {
        Some(_) => format!("\"texture reflectance\" \"t{i}\""),
        None => format!("\"rgb reflectance\" [ {} ]", rgb(m.base_color)),
    }
}

fn alpha(m: &MetallicRoughness) -> f32 {
    m.roughness * m.roughness
}

fn dielectric(i: usize, m: &MetallicRoughness) -> String {
    format!("\"string type\" \"diffuse\" {}", reflectance(i, m))
}

fn metal(i: usize, m: &MetallicRoughness) -> String {
    format!(
        "\"string type\" \"conductor\" {} \"float roughness\" [ {} ] \"bool remaproughness\" false",
        reflectance(i, m),
        alpha(m)
    )
}
