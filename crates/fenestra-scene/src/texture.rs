//! Image textures for reflectance and roughness (pbrt-v4's "imagemap").

use fenestra_core::image::Image;
use fenestra_core::{Rgb, Vec2};
use std::path::PathBuf;
use std::sync::Arc;

/// An image looked up by texture coordinates (pbrt-v4's "imagemap" parameters).
#[derive(Clone, Debug)]
pub struct ImageTexture {
    /// The texels (linear).
    pub image: Arc<Image>,
    /// The file it came from (kept for export).
    pub path: PathBuf,
    /// Multiplies every texel.
    pub scale: f32,
    /// Use 1 - value instead of the value.
    pub invert: bool,
    /// uv mapping: (u * uscale + udelta, v * vscale + vdelta).
    pub uscale: f32,
    /// See `uscale`.
    pub vscale: f32,
    /// See `uscale`.
    pub udelta: f32,
    /// See `uscale`.
    pub vdelta: f32,
}

impl ImageTexture {
    /// `image` from the file `path`, with the identity mapping.
    pub fn new(image: Arc<Image>, path: PathBuf) -> Self {
        ImageTexture {
            image,
            path,
            scale: 1.0,
            invert: false,
            uscale: 1.0,
            vscale: 1.0,
            udelta: 0.0,
            vdelta: 0.0,
        }
    }

    /// Bilinearly filtered, repeating lookup; as in pbrt-v4, v = 1 is the image's top row.
    pub fn lookup(&self, uv: Vec2) -> Rgb {
        let (w, h) = (self.image.width, self.image.height);
        let s = (uv.x * self.uscale + self.udelta) * w as f32 - 0.5;
        let t = (1.0 - (uv.y * self.vscale + self.vdelta)) * h as f32 - 0.5;
        if !(s.is_finite() && t.is_finite()) {
            return self.finish(Rgb::ZERO);
        }
        let (x0, y0) = (s.floor(), t.floor());
        let (fx, fy) = (s - x0, t - y0);
        let wrap = |v: f32, n: usize| (v as i64).rem_euclid(n as i64) as usize;
        let texel = |dx: f32, dy: f32| self.image.get(wrap(x0 + dx, w), wrap(y0 + dy, h));
        let c = texel(0.0, 0.0) * ((1.0 - fx) * (1.0 - fy))
            + texel(1.0, 0.0) * (fx * (1.0 - fy))
            + texel(0.0, 1.0) * ((1.0 - fx) * fy)
            + texel(1.0, 1.0) * (fx * fy);
        self.finish(c)
    }

    fn finish(&self, c: Rgb) -> Rgb {
        let c = c * self.scale;
        if self.invert {
            (Rgb::ONE - c).map(|v| v.max(0.0))
        } else {
            c
        }
    }

    /// The texture's mean value (used where a single reflectance is needed).
    pub fn average(&self) -> Rgb {
        self.finish(self.image.mean())
    }
}

/// GGX roughness varying over a surface: pbrt-v4's float image textures on a conductor's
/// "roughness", "uroughness" or "vroughness", looked up at each hit.
#[derive(Clone, Debug)]
pub struct RoughnessTexture {
    /// Roughness along the tangent, if a texture gives it.
    pub u: Option<Arc<ImageTexture>>,
    /// Roughness along the bitangent, if a texture gives it.
    pub v: Option<Arc<ImageTexture>>,
    /// pbrt-v4's "remaproughness": alpha = sqrt(roughness) when true.
    pub remap: bool,
}

/// GGX alpha below which pbrt-v4 treats a surface as smooth; the least a texture gives.
pub const MIN_ALPHA: f32 = 1e-3;

impl RoughnessTexture {
    /// (alpha_x, alpha_y) at `uv`: each texture's value (the mean of its channels), remapped
    /// and at least [`MIN_ALPHA`]; `constant` where no texture is given.
    pub fn alphas(&self, uv: Vec2, constant: (f32, f32)) -> (f32, f32) {
        let alpha = |t: &Option<Arc<ImageTexture>>, c: f32| match t {
            Some(t) => {
                let r = t.lookup(uv).average().max(0.0);
                (if self.remap { r.sqrt() } else { r }).max(MIN_ALPHA)
            }
            None => c,
        };
        (alpha(&self.u, constant.0), alpha(&self.v, constant.1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookup_flips_v_and_repeats() {
        let mut img = Image::new(2, 2);
        img.set(0, 0, Rgb::new(1.0, 0.0, 0.0)); // top left
        img.set(1, 1, Rgb::new(0.0, 0.0, 1.0)); // bottom right
        let t = ImageTexture::new(Arc::new(img), "t.png".into());
        // Texel centres: u = 0.25 is column 0, v = 0.75 is the top row.
        assert_eq!(t.lookup(Vec2::new(0.25, 0.75)), Rgb::new(1.0, 0.0, 0.0));
        assert_eq!(t.lookup(Vec2::new(0.75, 0.25)), Rgb::new(0.0, 0.0, 1.0));
        assert_eq!(t.lookup(Vec2::new(1.25, -0.25)), Rgb::new(1.0, 0.0, 0.0));
        assert_eq!(t.average(), Rgb::new(0.25, 0.0, 0.25));
    }
}
