//! pbrt-v4 materials mapped onto fenestra's. Approximations (docs/scenes.md):
//! - coateddiffuse and coatedconductor: pbrt-v4's random walk through the layers
//!   (fenestra-render's bsdf/layered), with its thickness, albedo, g, maxdepth and nsamples;
//! - smooth conductor (alpha < 1e-3): a mirror of the normal-incidence Fresnel reflectance;
//! - dielectric with spectral eta: the mean of the RGB values (no dispersion);
//! - anisotropic rough dielectric: alpha = sqrt(alpha_u alpha_v);
//! - mix: the material is chosen per point by a hash of the position, where pbrt-v4 hashes
//!   the position, direction and materials (the same mixture, another dither pattern).
//!
//! fenestra adds two types of its own so that its exports round-trip: "phong" (rgb diffuse,
//! rgb specular, float exponent) and "ward" (rgb diffuse, rgb specular, float alphax, alphay).

use crate::builder::{Builder, FloatTex, Tex};
use crate::params::ParamList;
use crate::spectra;
use crate::{Loc, PbrtError, Topic};
use fenestra_core::Rgb;
use fenestra_scene::material;
use fenestra_scene::material::{Relief, SMOOTH_ALPHA};
use fenestra_scene::{ImageTexture, Material, RoughnessTexture};
use std::path::Path;
use std::sync::Arc;

/// The note on rough coats, where fenestra's layered BSDF differs from pbrt-v4's by choice.
const ROUGH_COATS: &str =
    "rough coats of coated materials evaluated as their own sampling gives them \
    (pbrt-v4 weighs the walk's exits with the wrong density and its f comes out up to 8% brighter \
    than its sampling; docs/scenes.md)";

/// The note on normal maps.
const NORMAL_MAPS: &str = "normal maps: where a mapped normal turns away from the viewer, \
    reflected rays that would go through the surface are dropped (pbrt-v4 lets them through, \
    lighting such spots from behind the surface; docs/scenes.md)";

/// A reflectance as given: a value or a named texture.
enum Reflectance {
    Value(Rgb),
    Texture(Tex),
}

/// The material index of pbrt-v4's "interface": a boundary light passes unchanged (media
/// boundaries, exported portals); shapes with it are left out of the scene.
pub(super) const INTERFACE: usize = usize::MAX;

impl Builder {
    /// Creates the material and returns its index ([`INTERFACE`] for "interface").
    pub(super) fn material(
        &mut self,
        ty: &str,
        p: &ParamList,
        loc: &Loc,
        dir: &Path,
    ) -> Result<usize, PbrtError> {
        if ty == "interface" {
            p.use_all();
            return Ok(INTERFACE);
        }
        let rgb = |name: &str, default: Rgb| -> Result<Rgb, PbrtError> {
            match p.spectrum(name)? {
                Some((s, l)) => spectra::to_rgb(&s).map_err(|e| PbrtError::at(&l, e)),
                None => Ok(default),
            }
        };
        let m = match ty {
            "diffuse" => match self.reflectance(p, loc)? {
                Reflectance::Value(r) => Material::Diffuse(material::Diffuse { reflectance: r }),
                Reflectance::Texture(Tex::Rgb(r)) => {
                    Material::Diffuse(material::Diffuse { reflectance: r })
                }
                Reflectance::Texture(Tex::Image(texture)) => {
                    Material::TexturedDiffuse(material::TexturedDiffuse { texture })
                }
            },
            "coateddiffuse" => {
                let (r, texture) = match self.reflectance(p, loc)? {
                    Reflectance::Value(r) | Reflectance::Texture(Tex::Rgb(r)) => (r, None),
                    Reflectance::Texture(Tex::Image(t)) => (t.average(), Some(t)),
                };
                let eta = p.float("eta", 1.5)?;
                let alpha = self.alpha(p, loc)?.max(SMOOTH_ALPHA);
                if alpha > SMOOTH_ALPHA {
                    self.note(Topic::Materials, ROUGH_COATS, loc);
                }
                Material::CoatedDiffuse(material::CoatedDiffuse {
                    reflectance: r,
                    texture,
                    eta,
                    alpha,
                    layers: layers(p)?,
                })
            }
            "conductor" => {
                let textured = self.conductor_texture(p, loc)?;
                let (eta, k) = conductor_optics(p, "", textured)?;
                let map = self.roughness_texture(p)?;
                // With a texture, its means stand for it where one value is needed (quietly).
                let (au, av) = self.prefixed_alphas(p, "", loc, map.is_none())?;
                if map.is_none() && au.max(av) < SMOOTH_ALPHA {
                    let f0 =
                        |e: f32, k: f32| ((e - 1.0).powi(2) + k * k) / ((e + 1.0).powi(2) + k * k);
                    Material::Mirror(material::Mirror {
                        reflectance: Rgb::new(f0(eta.r, k.r), f0(eta.g, k.g), f0(eta.b, k.b)),
                    })
                } else {
                    Material::RoughConductor(material::RoughConductor {
                        eta,
                        k,
                        alpha_x: au.max(SMOOTH_ALPHA),
                        alpha_y: av.max(SMOOTH_ALPHA),
                        roughness: map.map(Arc::new),
                    })
                }
            }
            "coatedconductor" => {
                let (eta, k) = conductor_optics(p, "conductor.", None)?;
                let (au, av) = self.prefixed_alphas(p, "conductor.", loc, true)?;
                let (iu, iv) = self.prefixed_alphas(p, "interface.", loc, true)?;
                if (iu * iv).sqrt() > SMOOTH_ALPHA {
                    self.note(Topic::Materials, ROUGH_COATS, loc);
                }
                Material::CoatedConductor(material::CoatedConductor {
                    interface_eta: p.float("interface.eta", 1.5)?,
                    interface_alpha: (iu * iv).sqrt().max(SMOOTH_ALPHA),
                    eta,
                    k,
                    alpha_x: au.max(SMOOTH_ALPHA),
                    alpha_y: av.max(SMOOTH_ALPHA),
                    layers: layers(p)?,
                })
            }
            "dielectric" | "thindielectric" => {
                let eta = match p.spectrum("eta")? {
                    None => 1.5,
                    Some((s, l)) => {
                        let c = spectra::to_rgb(&s).map_err(|e| PbrtError::at(&l, e))?;
                        if c.max_component() - c.r.min(c.g).min(c.b) > 1e-6 {
                            self.warn(
                                Topic::Materials,
                                "dispersive (spectral) eta (the mean index is used)",
                                &l,
                            );
                        }
                        c.average()
                    }
                };
                if ty == "thindielectric" {
                    Material::ThinDielectric(material::ThinDielectric { eta })
                } else {
                    let (au, av) = self.alphas(p, loc)?;
                    if au.max(av) < SMOOTH_ALPHA {
                        Material::Dielectric(material::Dielectric { eta })
                    } else {
                        Material::RoughDielectric(material::RoughDielectric {
                            eta,
                            alpha: (au * av).sqrt().max(SMOOTH_ALPHA),
                        })
                    }
                }
            }
            "diffusetransmission" => {
                let scale = p.float("scale", 1.0)?;
                let mut albedo = |name: &str| -> Result<Rgb, PbrtError> {
                    let c = match self.spectrum_input(p, name, loc)? {
                        Some(Tex::Rgb(c)) => c,
                        Some(Tex::Image(t)) => {
                            self.warn(
                                Topic::Materials,
                                format!("diffusetransmission {name} texture (its mean is used)"),
                                loc,
                            );
                            t.average()
                        }
                        None => Rgb::splat(0.25),
                    };
                    Ok((c * scale).map(|v| v.clamp(0.0, 1.0)))
                };
                Material::DiffuseTransmission(material::DiffuseTransmission {
                    reflectance: albedo("reflectance")?,
                    transmittance: albedo("transmittance")?,
                })
            }
            "mix" => {
                let Some((names, at)) = p.strings("materials")? else {
                    return Err(PbrtError::at(
                        loc,
                        "mix material needs \"string materials\"",
                    ));
                };
                let [a, b] = &names[..] else {
                    return Err(PbrtError::at(
                        &at,
                        format!("mix takes two materials, found {}", names.len()),
                    ));
                };
                let index = |name: &String| {
                    self.named_materials.get(name).copied().ok_or_else(|| {
                        PbrtError::at(&at, format!("unknown named material \"{name}\""))
                    })
                };
                let materials = [index(a)?, index(b)?];
                let amount = self.float_or_texture(p, "amount", loc)?.unwrap_or(0.5);
                self.note(
                    Topic::Materials,
                    "mix chosen per point by a hash of the position (the same mixture as pbrt-v4, another dither pattern)",
                    loc,
                );
                if materials.contains(&INTERFACE) {
                    return Err(PbrtError::at(&at, "mix with an interface material"));
                }
                Material::Mix(material::Mix {
                    materials,
                    amount: amount.clamp(0.0, 1.0),
                })
            }
            "phong" => Material::Phong(material::Phong {
                diffuse: rgb("diffuse", Rgb::splat(0.5))?,
                specular: rgb("specular", Rgb::ZERO)?,
                exponent: p.float("exponent", 10.0)?,
            }),
            "ward" => Material::Ward(material::Ward {
                diffuse: rgb("diffuse", Rgb::splat(0.5))?,
                specular: rgb("specular", Rgb::splat(0.04))?,
                alpha_x: p.float("alphax", 0.1)?,
                alpha_y: p.float("alphay", 0.1)?,
            }),
            "" => return Ok(0),
            other => {
                self.warn(
                    Topic::Materials,
                    format!("Material \"{other}\" (replaced by diffuse 0.5)"),
                    loc,
                );
                p.use_all();
                Material::diffuse(0.5)
            }
        };
        if let Some(what) = m.validate() {
            return Err(PbrtError::at(loc, format!("material \"{ty}\": {what}")));
        }
        let relief = self.relief(p, loc, dir)?;
        self.materials.push(m);
        let index = self.materials.len() - 1;
        if let Some(relief) = relief {
            self.reliefs.insert(index, Arc::new(relief));
        }
        Ok(index)
    }

    /// The material's bump map ("texture displacement", a float image texture) or normal
    /// map ("string normalmap", an image of tangent-space normals read without sRGB
    /// decoding, as pbrt-v4 reads it). A constant displacement tilts nothing.
    fn relief(
        &mut self,
        p: &ParamList,
        loc: &Loc,
        dir: &Path,
    ) -> Result<Option<Relief>, PbrtError> {
        let normal_map = p.string("normalmap")?;
        let bump = match p.type_of("displacement") {
            Some("texture") => {
                let name = p.texture("displacement")?.unwrap_or_default();
                match self.float_textures.get(&name) {
                    Some(FloatTex::Image(t)) => Some(t.clone()),
                    Some(FloatTex::Value(_)) => None,
                    None => {
                        return Err(PbrtError::at(
                            loc,
                            format!("unknown float texture \"{name}\""),
                        ))
                    }
                }
            }
            Some(_) => {
                p.float("displacement", 0.0)?;
                None
            }
            None => None,
        };
        match (normal_map, bump) {
            (Some(file), bump) => {
                if bump.is_some() {
                    self.warn(
                        Topic::Materials,
                        "both a normal map and a displacement (the normal map is used, as pbrt-v4 does)",
                        loc,
                    );
                }
                let path = dir.join(&file);
                let image = self.data_image(&path, loc)?;
                self.note(Topic::Materials, NORMAL_MAPS, loc);
                Ok(Some(Relief::Normals(material::NormalMap {
                    texture: Arc::new(ImageTexture::new(image, path)),
                    scale: 1.0,
                })))
            }
            (None, Some(displacement)) => {
                Ok(Some(Relief::Bump(material::BumpMap { displacement })))
            }
            (None, None) => Ok(None),
        }
    }

    fn reflectance(&mut self, p: &ParamList, loc: &Loc) -> Result<Reflectance, PbrtError> {
        if p.type_of("reflectance") == Some("texture") {
            let name = p.texture("reflectance")?.unwrap_or_default();
            return match self.textures.get(&name) {
                Some(t) => Ok(Reflectance::Texture(t.clone())),
                None => Err(PbrtError::at(loc, format!("unknown texture \"{name}\""))),
            };
        }
        let r = match p.spectrum("reflectance")? {
            Some((s, l)) => spectra::to_rgb(&s).map_err(|e| PbrtError::at(&l, e))?,
            None => Rgb::splat(0.5),
        };
        if r.max_component() > 1.0 {
            // pbrt-v4 clamps reflectances to [0, 1]; a surface reflecting more than it
            // receives would make light out of nothing.
            self.warn(
                Topic::Materials,
                "reflectance above 1 (clamped to 1, as pbrt-v4 does)",
                loc,
            );
        }
        Ok(Reflectance::Value(r.map(|c| c.min(1.0))))
    }

    /// A conductor's "reflectance" given as a texture (as fenestra's exports of glTF metals
    /// write it): its mean colour, warned, since fenestra's conductor takes one complex index.
    fn conductor_texture(&mut self, p: &ParamList, loc: &Loc) -> Result<Option<Rgb>, PbrtError> {
        if p.type_of("reflectance") != Some("texture") {
            return Ok(None);
        }
        Ok(Some(match self.reflectance(p, loc)? {
            Reflectance::Texture(Tex::Image(t)) => {
                let mean = t.average();
                self.warn(
                    Topic::Materials,
                    format!(
                        "conductor reflectance texture {} (its mean colour is used)",
                        t.path.display()
                    ),
                    loc,
                );
                mean
            }
            Reflectance::Texture(Tex::Rgb(c)) | Reflectance::Value(c) => c,
        }))
    }

    /// A float parameter, which pbrt-v4 also lets name a float texture: fenestra's materials
    /// take constants, so a texture gives its average (warned), one it cannot read nothing.
    pub(super) fn float_or_texture(
        &mut self,
        p: &ParamList,
        name: &str,
        loc: &Loc,
    ) -> Result<Option<f32>, PbrtError> {
        self.float_input(p, name, loc, true)
    }

    /// [`Self::float_or_texture`], warning about a texture's average only with `warn`.
    fn float_input(
        &mut self,
        p: &ParamList,
        name: &str,
        loc: &Loc,
        warn: bool,
    ) -> Result<Option<f32>, PbrtError> {
        if p.type_of(name) != Some("texture") {
            return p.opt_float(name);
        }
        let texture = p.texture(name)?.unwrap_or_default();
        let value = match self.float_textures.get(&texture) {
            Some(t) => t.average(),
            None => {
                return Err(PbrtError::at(
                    loc,
                    format!("unknown float texture \"{texture}\""),
                ))
            }
        };
        let what = match value {
            Some(v) => format!("float texture for \"{name}\" (its average, {v}, is used)"),
            None => format!("float texture for \"{name}\" (the default is used)"),
        };
        if warn || value.is_none() {
            self.warn(Topic::Materials, what, loc);
        }
        Ok(value)
    }

    /// A conductor's roughness from float image textures, looked up at each hit: "roughness"
    /// for both directions unless "uroughness"/"vroughness" say otherwise.
    fn roughness_texture(&self, p: &ParamList) -> Result<Option<RoughnessTexture>, PbrtError> {
        let image = |name: &str| -> Result<Option<Arc<ImageTexture>>, PbrtError> {
            if p.type_of(name) != Some("texture") {
                return Ok(None);
            }
            let texture = p.texture(name)?.unwrap_or_default();
            Ok(match self.float_textures.get(&texture) {
                Some(FloatTex::Image(t)) => Some(t.clone()),
                _ => None,
            })
        };
        let both = image("roughness")?;
        let either = |name: &str| -> Result<Option<Arc<ImageTexture>>, PbrtError> {
            Ok(if p.has(name) {
                image(name)?
            } else {
                both.clone()
            })
        };
        let (u, v) = (either("uroughness")?, either("vroughness")?);
        if u.is_none() && v.is_none() {
            return Ok(None);
        }
        Ok(Some(RoughnessTexture {
            u,
            v,
            remap: p.bool("remaproughness", true)?,
        }))
    }

    /// GGX (alpha_u, alpha_v) from "roughness" or "uroughness"/"vroughness"; pbrt-v4 remaps
    /// roughness r to alpha = sqrt(r) unless "remaproughness" is false.
    fn alphas(&mut self, p: &ParamList, loc: &Loc) -> Result<(f32, f32), PbrtError> {
        self.prefixed_alphas(p, "", loc, true)
    }

    /// [`Self::alphas`] of the parameters named `prefix`roughness (a layer's, in coated
    /// materials: "interface." or "conductor.").
    fn prefixed_alphas(
        &mut self,
        p: &ParamList,
        prefix: &str,
        loc: &Loc,
        warn: bool,
    ) -> Result<(f32, f32), PbrtError> {
        let name = |n: &str| format!("{prefix}{n}");
        let r = self
            .float_input(p, &name("roughness"), loc, warn)?
            .unwrap_or(0.0);
        let u = self
            .float_input(p, &name("uroughness"), loc, warn)?
            .unwrap_or(r);
        let v = self
            .float_input(p, &name("vroughness"), loc, warn)?
            .unwrap_or(r);
        let remap = p.bool("remaproughness", true)?;
        let a = |x: f32| if remap { x.max(0.0).sqrt() } else { x };
        Ok((a(u), a(v)))
    }

    fn alpha(&mut self, p: &ParamList, loc: &Loc) -> Result<f32, PbrtError> {
        let (u, v) = self.alphas(p, loc)?;
        Ok((u * v).sqrt())
    }
}

/// A conductor's complex index from `prefix`eta and `prefix`k (copper by default), or from
/// "reflectance" (a value, or `textured`'s colour) as pbrt-v4 reads it: eta = 1 and
/// k = 2 sqrt(r) / sqrt(1 - r) reproduce r at normal incidence.
fn conductor_optics(
    p: &ParamList,
    prefix: &str,
    textured: Option<Rgb>,
) -> Result<(Rgb, Rgb), PbrtError> {
    let rgb = |name: &str, default: &str| -> Result<Rgb, PbrtError> {
        match p.spectrum(&format!("{prefix}{name}"))? {
            Some((s, l)) => spectra::to_rgb(&s).map_err(|e| PbrtError::at(&l, e)),
            None => Ok(spectra::named(default).unwrap_or(Rgb::ONE)),
        }
    };
    let reflectance = match textured {
        Some(r) => Some(r),
        None => match p.spectrum("reflectance")? {
            Some((s, l)) => Some(spectra::to_rgb(&s).map_err(|e| PbrtError::at(&l, e))?),
            None => None,
        },
    };
    Ok(match reflectance {
        Some(r) => {
            let k = r.map(|v| {
                let v = v.clamp(0.0, 0.9999);
                2.0 * v.sqrt() / (1.0 - v).sqrt()
            });
            (Rgb::ONE, k)
        }
        None => (rgb("eta", "metal-Cu-eta")?, rgb("k", "metal-Cu-k")?),
    })
}

/// The slab of a coated material: pbrt-v4's "thickness", "albedo", "g", "maxdepth" and
/// "nsamples", with its defaults.
fn layers(p: &ParamList) -> Result<material::Layers, PbrtError> {
    let d = material::Layers::default();
    let albedo = match p.spectrum("albedo")? {
        Some((s, l)) => spectra::to_rgb(&s).map_err(|e| PbrtError::at(&l, e))?,
        None => d.albedo,
    };
    let count = |name: &str, default: u32| -> Result<u32, PbrtError> {
        Ok(p.int(name, i64::from(default))?
            .clamp(0, i64::from(u32::MAX)) as u32)
    };
    Ok(material::Layers {
        thickness: p.float("thickness", d.thickness)?,
        albedo,
        g: p.float("g", d.g)?,
        max_depth: count("maxdepth", d.max_depth)?,
        samples: count("nsamples", d.samples)?,
    })
}
