//! Texture directives: named spectrum textures (constants, image maps, checkerboards and
//! what they average to), float textures, and the images they read.

use crate::builder::{Builder, FloatTex, Tex};
use crate::params::ParamList;
use crate::parser::Directive;
use crate::{Loc, PbrtError, Topic};
use fenestra_core::image::Image;
use fenestra_core::Rgb;
use fenestra_scene::texture::ImageTexture;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Texels along a check of a checkerboard texture.
const CHECK_TEXELS: usize = 64;

impl Builder {
    pub(crate) fn texture(&mut self, d: &Directive, dir: &Path) -> Result<(), PbrtError> {
        let (name, ty, class) = (d.str(0), d.str(1), d.str(2));
        let p = &d.params;
        if ty == "float" {
            let value = match class {
                "constant" => FloatTex::Value(Some(p.float("value", 1.0)?)),
                "imagemap" => FloatTex::Image(Arc::new(self.image_texture(d, dir)?)),
                "checkerboard" => {
                    let (a, b) = (p.float("tex1", 1.0)?, p.float("tex2", 0.0)?);
                    p.use_all();
                    FloatTex::Value(Some(0.5 * (a + b)))
                }
                _ => {
                    self.warn(Topic::Textures,
                        format!("float Texture class \"{class}\" (materials using it keep their defaults)"),
                        &d.loc,
                    );
                    p.use_all();
                    FloatTex::Value(None)
                }
            };
            self.float_textures.insert(name.into(), value);
            return Ok(());
        }
        let tex = match class {
            "imagemap" => Tex::Image(Arc::new(self.image_texture(d, dir)?)),
            "scale" => {
                let tex = self.spectrum_input(p, "tex", &d.loc)?;
                let scale = self.float_or_texture(p, "scale", &d.loc)?.unwrap_or(1.0);
                match tex {
                    Some(Tex::Rgb(c)) => Tex::Rgb(c * scale),
                    // Exact: the image's own scale comes before its inversion.
                    Some(Tex::Image(t)) if !t.invert => {
                        let mut t = (*t).clone();
                        t.scale *= scale;
                        Tex::Image(Arc::new(t))
                    }
                    Some(Tex::Image(t)) => {
                        self.warn(
                            Topic::Textures,
                            "scale of an inverted image texture (its mean is used)",
                            &d.loc,
                        );
                        Tex::Rgb(t.average() * scale)
                    }
                    None => Tex::Rgb(Rgb::splat(scale)),
                }
            }
            "checkerboard" => self.checkerboard(p, &d.loc)?,
            "mix" => {
                let one = self.spectrum_input(p, "tex1", &d.loc)?;
                let two = self.spectrum_input(p, "tex2", &d.loc)?;
                let amount = self.float_or_texture(p, "amount", &d.loc)?.unwrap_or(0.5);
                let value = |t: Option<Tex>, default: f32| match t {
                    Some(Tex::Rgb(c)) => (c, false),
                    Some(Tex::Image(t)) => (t.average(), true),
                    None => (Rgb::splat(default), false),
                };
                let ((a, a_image), (b, b_image)) = (value(one, 0.0), value(two, 1.0));
                if a_image || b_image {
                    self.warn(
                        Topic::Textures,
                        "mix of image textures (their means are mixed)",
                        &d.loc,
                    );
                }
                Tex::Rgb(a * (1.0 - amount) + b * amount)
            }
            "constant" => Tex::Rgb(match p.spectrum("value")? {
                Some((s, loc)) => crate::spectra::to_rgb(&s).map_err(|e| PbrtError::at(&loc, e))?,
                None => Rgb::ONE,
            }),
            _ => {
                self.warn(
                    Topic::Textures,
                    format!("Texture class \"{class}\" (replaced by 0.5 grey)"),
                    &d.loc,
                );
                p.use_all();
                Tex::Rgb(Rgb::splat(0.5))
            }
        };
        self.textures.insert(name.into(), tex);
        Ok(())
    }

    /// pbrt-v4's 2D checkerboard over (u, v) as an image texture of one 2x2 period: `tex1`
    /// where floor(s) + floor(t) is even, `tex2` elsewhere, with s = u uscale + udelta and
    /// t = v vscale + vdelta. Bilinear lookup blurs each edge over one of a check's
    /// [`CHECK_TEXELS`] texels; image inputs give their means (warned).
    fn checkerboard(&mut self, p: &ParamList, loc: &Loc) -> Result<Tex, PbrtError> {
        if p.int("dimension", 2)? != 2 {
            return Err(PbrtError::at(
                loc,
                "checkerboard: only dimension 2 is supported",
            ));
        }
        if p.string("mapping")?.is_some_and(|m| m != "uv") {
            self.warn(
                Topic::Textures,
                "checkerboard mapping other than uv (uv is used)",
                loc,
            );
        }
        let mut input = |name: &str, default: f32| -> Result<Rgb, PbrtError> {
            Ok(match self.spectrum_input(p, name, loc)? {
                Some(Tex::Rgb(c)) => c,
                Some(Tex::Image(t)) => {
                    self.warn(
                        Topic::Textures,
                        "checkerboard of image textures (their means are used)",
                        loc,
                    );
                    t.average()
                }
                None => Rgb::splat(default),
            })
        };
        let (one, two) = (input("tex1", 1.0)?, input("tex2", 0.0)?);
        let n = CHECK_TEXELS;
        let mut image = Image::new(2 * n, 2 * n);
        for y in 0..2 * n {
            for x in 0..2 * n {
                // Row y holds t in (1 - y / n) mod 2 (v = 1 is the top row), column x s = x / n.
                let even = (x / n + y / n) % 2 == 1;
                image.set(x, y, if even { one } else { two });
            }
        }
        let mut t = ImageTexture::new(Arc::new(image), PathBuf::from("checkerboard"));
        // The image is one 2x2 period: half the scale and offset of the checks.
        t.uscale = 0.5 * p.float("uscale", 1.0)?;
        t.vscale = 0.5 * p.float("vscale", 1.0)?;
        t.udelta = 0.5 * p.float("udelta", 0.0)?;
        t.vdelta = 0.5 * p.float("vdelta", 0.0)?;
        Ok(Tex::Image(Arc::new(t)))
    }

    /// A spectrum texture's input `name`: a named texture or a value, if given.
    pub(crate) fn spectrum_input(
        &mut self,
        p: &ParamList,
        name: &str,
        loc: &Loc,
    ) -> Result<Option<Tex>, PbrtError> {
        if p.type_of(name) == Some("texture") {
            let texture = p.texture(name)?.unwrap_or_default();
            return match self.textures.get(&texture) {
                Some(t) => Ok(Some(t.clone())),
                None => Err(PbrtError::at(loc, format!("unknown texture \"{texture}\""))),
            };
        }
        Ok(match p.spectrum(name)? {
            Some((s, l)) => Some(Tex::Rgb(
                crate::spectra::to_rgb(&s).map_err(|e| PbrtError::at(&l, e))?,
            )),
            None => None,
        })
    }

    /// The image texture of an "imagemap" Texture directive.
    fn image_texture(&mut self, d: &Directive, dir: &Path) -> Result<ImageTexture, PbrtError> {
        let p = &d.params;
        let Some(file) = p.string("filename")? else {
            return Err(PbrtError::at(
                &d.loc,
                format!(
                    "imagemap texture \"{}\" needs \"string filename\"",
                    d.str(0)
                ),
            ));
        };
        let path = dir.join(&file);
        let image = self.image(&path, &d.loc)?;
        let mut t = ImageTexture::new(image, path.clone());
        t.scale = p.float("scale", 1.0)?;
        t.invert = p.bool("invert", false)?;
        t.uscale = p.float("uscale", 1.0)?;
        t.vscale = p.float("vscale", 1.0)?;
        t.udelta = p.float("udelta", 0.0)?;
        t.vdelta = p.float("vdelta", 0.0)?;
        p.string("filter")?;
        p.float("maxanisotropy", 8.0)?;
        if let Some(w) = p.string("wrap")?.filter(|w| w != "repeat") {
            self.warn(
                Topic::Textures,
                format!("texture wrap mode \"{w}\" (textures repeat)"),
                &d.loc,
            );
        }
        if let Some(m) = p.string("mapping")?.filter(|m| m != "uv") {
            self.warn(
                Topic::Textures,
                format!("texture mapping \"{m}\" (uv mapping is used)"),
                &d.loc,
            );
        }
        if let Some(e) = p.string("encoding")? {
            let eight_bit = path.extension().is_some_and(|x| {
                ["png", "tga", "jpg", "jpeg"]
                    .iter()
                    .any(|k| x.eq_ignore_ascii_case(k))
            });
            if !(eight_bit && e == "sRGB" || !eight_bit && e == "linear") {
                self.warn(Topic::Textures,
                    format!("texture encoding \"{e}\" (PNG, TGA and JPEG are read as sRGB, EXR, HDR and PFM as linear)"),
                    &d.loc,
                );
            }
        }
        Ok(t)
    }

    /// An image file, read once however many textures or lights use it.
    pub fn image(&mut self, path: &Path, loc: &Loc) -> Result<Arc<Image>, PbrtError> {
        self.read_image(path, loc, true)
    }

    /// An image of data (a normal map): 8-bit values as stored, not decoded from sRGB.
    pub fn data_image(&mut self, path: &Path, loc: &Loc) -> Result<Arc<Image>, PbrtError> {
        self.read_image(path, loc, false)
    }

    fn read_image(&mut self, path: &Path, loc: &Loc, srgb: bool) -> Result<Arc<Image>, PbrtError> {
        let key = (path.to_path_buf(), srgb);
        if let Some(img) = self.images.get(&key) {
            return Ok(img.clone());
        }
        let read = if srgb { Image::read } else { Image::read_data };
        let img = Arc::new(read(path).map_err(|e| PbrtError::at(loc, e.to_string()))?);
        self.files.push(path.to_path_buf());
        self.images.insert(key, img.clone());
        Ok(img)
    }
}
