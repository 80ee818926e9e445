//! glTF materials as fenestra materials: metallic-roughness with its textures, normal map,
//! ior and specular; transmission as a mix with glass (thin unless KHR_materials_volume
//! gives it thickness); emission as the shape's area light.

use crate::error::GltfError;
use crate::images::{Encoding, Images};
use crate::report::Report;
use crate::source::Source;
use fenestra_core::Rgb;
use fenestra_scene::light::Emission;
use fenestra_scene::material::{self, Alpha, AlphaMode, MetallicRoughness, NormalMap};
use fenestra_scene::texture::ImageTexture;
use fenestra_scene::Material;
use std::sync::Arc;

/// The scene's materials and, per glTF material, its index among them and its emission.
pub struct Materials {
    /// Every material (a transmissive glTF material adds its glass and the mix).
    pub materials: Vec<Material>,
    /// Per glTF material: the index in `materials` and the emitted radiance, if any.
    pub of_gltf: Vec<(usize, Option<Emission>)>,
    /// The material of primitives that name none (glTF's default: white, metallic, rough).
    pub default: usize,
}

/// A texture reference: the glTF texture index and the JSON pointer naming it.
struct TextureRef {
    texture: usize,
    at: String,
    tex_coord: u32,
    transform: Option<([f32; 2], f32, [f32; 2])>,
}

impl TextureRef {
    fn of(info: &gltf::texture::Info, at: String) -> Self {
        TextureRef {
            texture: info.texture().index(),
            at,
            tex_coord: info.tex_coord(),
            transform: info
                .texture_transform()
                .map(|t| (t.offset(), t.rotation(), t.scale())),
        }
    }
}

/// The images `materials` will ask for, so that they can be decoded together first.
pub fn wanted_images(doc: &gltf::Document) -> Vec<(usize, Encoding)> {
    let mut out = Vec::new();
    for m in doc.materials() {
        let pbr = m.pbr_metallic_roughness();
        let mut want = |t: Option<gltf::Texture>, e: Encoding| {
            if let Some(image) = t.and_then(|t| t.source()) {
                if !out.contains(&(image.index(), e)) {
                    out.push((image.index(), e));
                }
            }
        };
        want(
            pbr.base_color_texture().map(|i| i.texture()),
            Encoding::Srgb,
        );
        want(
            pbr.metallic_roughness_texture().map(|i| i.texture()),
            Encoding::Linear,
        );
        want(m.normal_texture().map(|n| n.texture()), Encoding::Linear);
        want(m.emissive_texture().map(|i| i.texture()), Encoding::Srgb);
        if m.alpha_mode() != gltf::material::AlphaMode::Opaque {
            want(
                pbr.base_color_texture().map(|i| i.texture()),
                Encoding::Alpha,
            );
        }
    }
    out
}

/// Builds every material of `src`.
pub fn build(src: &Source, images: &Images, report: &mut Report) -> Result<Materials, GltfError> {
    let mut out = Materials {
        materials: Vec::new(),
        of_gltf: Vec::new(),
        default: 0,
    };
    out.materials
        .push(Material::MetallicRoughness(MetallicRoughness::new()));
    for m in src.document.materials() {
        let at = format!("/materials/{}", m.index().unwrap_or(0));
        let surface = out.materials.len();
        out.materials.push(Material::MetallicRoughness(one(
            src, images, &m, &at, report,
        )?));
        if let Some((glass, amount)) = transmission(&m, &at, report) {
            out.materials.push(glass);
            out.materials.push(Material::Mix(material::Mix {
                materials: [surface, surface + 1],
                amount,
            }));
        }
        let index = out.materials.len() - 1;
        out.of_gltf
            .push((index, emission(src, images, &m, &at, report)?));
    }
    Ok(out)
}

/// The metallic-roughness part of glTF material `m`.
fn one(
    src: &Source,
    images: &Images,
    m: &gltf::Material,
    at: &str,
    report: &mut Report,
) -> Result<MetallicRoughness, GltfError> {
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, _] = pbr.base_color_factor();
    let tex = |info: Option<gltf::texture::Info>, path: &str, e, report: &mut Report| {
        info.map(|i| {
            texture(
                src,
                images,
                TextureRef::of(&i, format!("{at}/{path}")),
                e,
                report,
            )
        })
        .transpose()
        .map(Option::flatten)
    };
    let mut built = MetallicRoughness {
        base_color: Rgb::new(r, g, b),
        base_color_texture: tex(
            pbr.base_color_texture(),
            "pbrMetallicRoughness/baseColorTexture",
            Encoding::Srgb,
            report,
        )?,
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        metallic_roughness_texture: tex(
            pbr.metallic_roughness_texture(),
            "pbrMetallicRoughness/metallicRoughnessTexture",
            Encoding::Linear,
            report,
        )?,
        ior: m.ior().unwrap_or(1.5),
        specular: 1.0,
        specular_color: Rgb::ONE,
        normal_map: None,
        alpha: None,
    };
    if let Some(n) = m.normal_texture() {
        let t = TextureRef {
            texture: n.texture().index(),
            at: format!("{at}/normalTexture"),
            tex_coord: n.tex_coord(),
            transform: None,
        };
        built.normal_map =
            texture(src, images, t, Encoding::Linear, report)?.map(|texture| NormalMap {
                texture,
                scale: n.scale(),
            });
    }
    if let Some(s) = m.specular() {
        built.specular = s.specular_factor();
        built.specular_color = Rgb::from(s.specular_color_factor());
        if s.specular_texture().is_some() || s.specular_color_texture().is_some() {
            report.say(
                format!("{at}/extensions/KHR_materials_specular"),
                "specular textures are not supported (the factors are used)",
            );
        }
    }
    amd_split_roughness_metallic(m, at, &mut built, report);
    if m.occlusion_texture().is_some() {
        report.say(format!("{at}/occlusionTexture"), "occlusion textures are a baking hint for rasterisers: ignored (a path tracer computes occlusion)");
    }
    built.alpha = alpha(src, images, m, at, report)?;
    if let Some(what) = built.validate() {
        return Err(GltfError::at(&src.path, at, what));
    }
    Ok(built)
}

/// The cut-out of a MASK or BLEND material: base colour alpha factor times its texture's
/// alpha.
fn alpha(
    src: &Source,
    images: &Images,
    m: &gltf::Material,
    at: &str,
    report: &mut Report,
) -> Result<Option<Alpha>, GltfError> {
    let mode = match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => return Ok(None),
        gltf::material::AlphaMode::Mask => AlphaMode::Mask {
            cutoff: m.alpha_cutoff().unwrap_or(0.5),
        },
        gltf::material::AlphaMode::Blend => AlphaMode::Blend,
    };
    let pbr = m.pbr_metallic_roughness();
    let texture = match pbr.base_color_texture() {
        Some(info) => {
            let t = TextureRef::of(&info, format!("{at}/pbrMetallicRoughness/baseColorTexture"));
            texture(src, images, t, Encoding::Alpha, report)?
        }
        None => None,
    };
    Ok(Some(Alpha {
        factor: pbr.base_color_factor()[3],
        texture,
        mode,
    }))
}

/// AMD's vendor extension that splits the metallic-roughness texture in two. Its textures
/// come as DDS, which fenestra does not decode: the roughness factor stands, and a material
/// whose metalness was to come from a texture is taken as a dielectric (the factor, 1 by
/// default, is only meant to scale that texture; fabrics would otherwise render as metal).
fn amd_split_roughness_metallic(
    m: &gltf::Material,
    at: &str,
    built: &mut MetallicRoughness,
    report: &mut Report,
) {
    let Some(ext) = m.extension_value("AMD_split_roughnessMetallic") else {
        return;
    };
    if ext.get("metallicTexture").is_some() {
        built.metallic = 0.0;
    }
    report.say(
        format!("{at}/extensions/AMD_split_roughnessMetallic"),
        "AMD_split_roughnessMetallic's textures are not read: roughness is its factor, and metalness 0 where a texture was to give it",
    );
}

/// The glass a transmissive material mixes with, and the mix amount.
fn transmission(m: &gltf::Material, at: &str, report: &mut Report) -> Option<(Material, f32)> {
    let t = m.transmission()?;
    if t.transmission_factor() <= 0.0 {
        return None;
    }
    if t.transmission_texture().is_some() {
        report.say(
            format!("{at}/extensions/KHR_materials_transmission"),
            "transmission textures are not supported (the factor is used)",
        );
    }
    let eta = m.ior().unwrap_or(1.5);
    let roughness = m.pbr_metallic_roughness().roughness_factor();
    let thick = m.volume().is_some_and(|v| v.thickness_factor() > 0.0);
    let glass = match (thick, roughness * roughness) {
        (false, _) => Material::ThinDielectric(material::ThinDielectric { eta }),
        (true, a) if a < 1e-3 => Material::Dielectric(material::Dielectric { eta }),
        (true, alpha) => Material::RoughDielectric(material::RoughDielectric { eta, alpha }),
    };
    if !thick && roughness > 0.0 {
        report.say(
            format!("{at}/extensions/KHR_materials_transmission"),
            "rough thin-walled transmission is smooth thin glass",
        );
    }
    let metallic = m.pbr_metallic_roughness().metallic_factor();
    Some((glass, t.transmission_factor() * (1.0 - metallic)))
}

/// The radiance a material emits: emissive factor times strength (times the emissive
/// texture's mean: emission is uniform over a shape).
fn emission(
    src: &Source,
    images: &Images,
    m: &gltf::Material,
    at: &str,
    report: &mut Report,
) -> Result<Option<Emission>, GltfError> {
    let mut radiance = Rgb::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0);
    if let Some(info) = m.emissive_texture() {
        let t = TextureRef::of(&info, format!("{at}/emissiveTexture"));
        if let Some(texture) = texture(src, images, t, Encoding::Srgb, report)? {
            radiance *= texture.average();
            report.say(
                format!("{at}/emissiveTexture"),
                "emissive textures emit their mean over the surface",
            );
        }
    }
    if radiance.max_component() <= 0.0 {
        return Ok(None);
    }
    Ok(Some(Emission {
        radiance,
        two_sided: m.double_sided(),
    }))
}

/// The image texture a reference names, or `None` (said in the report) when its image
/// cannot be decoded (a DDS-only texture).
fn texture(
    src: &Source,
    images: &Images,
    t: TextureRef,
    encoding: Encoding,
    report: &mut Report,
) -> Result<Option<Arc<ImageTexture>>, GltfError> {
    let Some(texture) = src.document.textures().nth(t.texture) else {
        return Err(GltfError::at(
            &src.path,
            &t.at,
            format!("texture {} out of range", t.texture),
        ));
    };
    let Some(image) = texture.source() else {
        report.say(
            &t.at,
            "texture without a PNG or JPEG source (only an extension's, e.g. DDS): left out",
        );
        return Ok(None);
    };
    let (image, path) = images
        .get(image.index(), encoding)
        .ok_or_else(|| GltfError::at(&src.path, &t.at, "texture image was not decoded"))?;
    let sampler = texture.sampler();
    let repeat = gltf::texture::WrappingMode::Repeat;
    if sampler.wrap_s() != repeat || sampler.wrap_t() != repeat {
        report.say(
            &t.at,
            "clamped and mirrored texture wrapping are not supported (textures repeat)",
        );
    }
    if t.tex_coord != 0 {
        report.say(
            &t.at,
            "texture coordinates other than TEXCOORD_0 are not supported (TEXCOORD_0 is used)",
        );
    }
    let mut it = ImageTexture::new(image.clone(), path.clone());
    if let Some((offset, rotation, scale)) = t.transform {
        if rotation != 0.0 {
            report.say(
                &t.at,
                "KHR_texture_transform rotation is not supported (offset and scale are used)",
            );
        }
        // glTF's v runs down the image, fenestra's (pbrt's) up: with v' = 1 - v,
        // v_gltf -> s v_gltf + o becomes v' -> s v' + (1 - s - o).
        it.uscale = scale[0];
        it.udelta = offset[0];
        it.vscale = scale[1];
        it.vdelta = 1.0 - scale[1] - offset[1];
    }
    Ok(Some(Arc::new(it)))
}
