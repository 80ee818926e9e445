//! Error of an image against a reference, and efficiency = 1 / (MSE x time) (seed 000 §4.3).

use crate::EvalError;
use fenestra_core::image::Image;
use serde::{Deserialize, Serialize};

/// The error of an image against a reference.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// Mean squared error over all pixels and channels.
    pub mse: f64,
    /// Mean of (x - r)^2 / (r^2 + 0.01): relative error that does not explode on black.
    pub rel_mse: f64,
    /// Mean absolute error.
    pub mae: f64,
    /// Mean of the image (all channels).
    pub mean: f64,
    /// Mean of the reference.
    pub ref_mean: f64,
}

/// Compares `img` with `reference` channel by channel.
pub fn compare(img: &Image, reference: &Image) -> Result<Metrics, EvalError> {
    if (img.width, img.height) != (reference.width, reference.height) {
        return Err(EvalError::SizeMismatch(
            img.width,
            img.height,
            reference.width,
            reference.height,
        ));
    }
    for (image, which) in [(img, "image"), (reference, "reference")] {
        let bad = image.pixels.iter().filter(|p| !p.is_finite()).count();
        if bad > 0 {
            return Err(EvalError::NonFinite { which, pixels: bad });
        }
    }
    let (mut se, mut rel, mut ae, mut sum, mut ref_sum) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (p, r) in img.pixels.iter().zip(&reference.pixels) {
        for (x, r) in p.to_array().into_iter().zip(r.to_array()) {
            let (x, r) = (x as f64, r as f64);
            let d = x - r;
            se += d * d;
            rel += d * d / (r * r + 0.01);
            ae += d.abs();
            sum += x;
            ref_sum += r;
        }
    }
    let n = (img.pixels.len() * 3).max(1) as f64;
    Ok(Metrics {
        mse: se / n,
        rel_mse: rel / n,
        mae: ae / n,
        mean: sum / n,
        ref_mean: ref_sum / n,
    })
}

/// Efficiency 1 / (MSE x time): how much error a second of rendering removes; infinite
/// for an exact image.
pub fn efficiency(mse: f64, time_s: f64) -> f64 {
    1.0 / (mse * time_s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Rgb;

    #[test]
    fn metrics_match_hand_computed_values() {
        // Reference: pixels (1,1,1) and (0,0,0); image: (2,1,1) and (0,0.5,0).
        let mut r = Image::new(2, 1);
        r.set(0, 0, Rgb::ONE);
        let mut x = Image::new(2, 1);
        x.set(0, 0, Rgb::new(2.0, 1.0, 1.0));
        x.set(1, 0, Rgb::new(0.0, 0.5, 0.0));
        let m = compare(&x, &r).expect("same size");
        // Squared errors: 1, 0, 0, 0, 0.25, 0 -> mse 1.25 / 6.
        assert!((m.mse - 1.25 / 6.0).abs() < 1e-12);
        // Relative: 1 / 1.01 + 0.25 / 0.01 = 0.990099 + 25 -> / 6.
        assert!((m.rel_mse - (1.0 / 1.01 + 25.0) / 6.0).abs() < 1e-9);
        assert!((m.mae - 1.5 / 6.0).abs() < 1e-12);
        assert!((m.mean - 4.5 / 6.0).abs() < 1e-12 && (m.ref_mean - 0.5).abs() < 1e-12);
        assert_eq!(efficiency(0.25, 2.0), 2.0);
        assert!(efficiency(0.0, 1.0).is_infinite());
        assert!(matches!(
            compare(&Image::new(1, 1), &r),
            Err(EvalError::SizeMismatch(1, 1, 2, 1))
        ));
    }
}
