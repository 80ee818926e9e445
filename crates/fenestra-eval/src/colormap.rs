//! False-colour error maps (seed 000 Fig. 5.4 style) written as PNG.

use crate::EvalError;
use fenestra_core::fs::write_atomically;
use fenestra_core::image::Image;
use std::path::Path;

/// Samples of matplotlib's "inferno" colour map at 0, 1/6, ..., 1 (sRGB bytes): perceptually
/// ordered from black through purple and orange to pale yellow.
const INFERNO: [[f32; 3]; 7] = [
    [0.0, 0.0, 4.0],
    [40.0, 11.0, 84.0],
    [101.0, 21.0, 110.0],
    [159.0, 42.0, 99.0],
    [212.0, 72.0, 66.0],
    [245.0, 125.0, 21.0],
    [252.0, 255.0, 164.0],
];

/// Colour of `t` in [0, 1].
pub fn inferno(t: f32) -> [u8; 3] {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    } * 6.0;
    let i = (t as usize).min(5);
    let f = t - i as f32;
    std::array::from_fn(|c| (INFERNO[i][c] * (1.0 - f) + INFERNO[i + 1][c] * f).round() as u8)
}

/// Per-pixel relative squared error (luminance) against the reference, on a log scale from
/// 1e-4 (black) to 10 (pale yellow), the same for every image of a report.
pub fn write_error_map(img: &Image, reference: &Image, path: &Path) -> Result<(), EvalError> {
    if (img.width, img.height) != (reference.width, reference.height) {
        return Err(EvalError::SizeMismatch(
            img.width,
            img.height,
            reference.width,
            reference.height,
        ));
    }
    let (lo, hi) = (1e-4f32.log10(), 10f32.log10());
    let mut bytes = Vec::with_capacity(img.pixels.len() * 3);
    for (p, r) in img.pixels.iter().zip(&reference.pixels) {
        let (x, r) = (p.luminance(), r.luminance());
        let rel = (x - r) * (x - r) / (r * r + 0.01);
        bytes.extend(inferno((rel.max(1e-12).log10() - lo) / (hi - lo)));
    }
    let buf =
        image::RgbImage::from_raw(img.width as u32, img.height as u32, bytes).ok_or_else(|| {
            EvalError::File {
                path: path.display().to_string(),
                reason: "bad image size".into(),
            }
        })?;
    Ok(write_atomically(path, |tmp| {
        buf.save_with_format(tmp, image::ImageFormat::Png)
    })?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_map_ends_and_order() {
        assert_eq!(inferno(0.0), [0, 0, 4]);
        assert_eq!(inferno(1.0), [252, 255, 164]);
        assert_eq!(inferno(f32::NAN), [0, 0, 4]);
        let lum = |c: [u8; 3]| 0.2126 * c[0] as f32 + 0.7152 * c[1] as f32 + 0.0722 * c[2] as f32;
        assert!(
            (0..10).all(|i| lum(inferno(i as f32 / 10.0)) < lum(inferno((i + 1) as f32 / 10.0)))
        );
    }
}
