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
    /// Error of the means of an 8 x 8 grid of regions: the sum over regions and channels of
    /// |image mean - reference mean| over the sum of the reference means. Unlike the MSE it
    /// hardly moves with noise, so it tells a different picture from a noisy one.
    #[serde(default)]
    pub region_error: f64,
    /// The share of [`Metrics::rel_mse`]'s sum in the worst 1% of pixels (at least one): 0.01
    /// when the relative error is spread evenly, near 1 when a few pixels (fireflies, edges,
    /// corners) carry it.
    #[serde(default)]
    pub worst_share: f64,
}

/// The share of `errors`' sum in its largest hundredth (at least one; 0 for a zero sum).
fn worst_share(mut errors: Vec<f64>) -> f64 {
    let total: f64 = errors.iter().sum();
    if errors.is_empty() || total <= 0.0 {
        return 0.0;
    }
    let worst = errors.len().div_ceil(100);
    errors.select_nth_unstable_by(worst - 1, |a, b| b.total_cmp(a));
    errors[..worst].iter().sum::<f64>() / total
}

/// Regions per side of [`Metrics::region_error`]'s grid.
pub const REGIONS: usize = 8;

/// The mean of each channel over each region of a `REGIONS` x `REGIONS` grid.
fn region_means(img: &Image) -> Vec<[f64; 3]> {
    let mut sums = vec![([0.0f64; 3], 0usize); REGIONS * REGIONS];
    for y in 0..img.height {
        let ry = y * REGIONS / img.height.max(1);
        for x in 0..img.width {
            let rx = x * REGIONS / img.width.max(1);
            let (sum, n) = &mut sums[ry * REGIONS + rx];
            for (s, v) in sum.iter_mut().zip(img.get(x, y).to_array()) {
                *s += v as f64;
            }
            *n += 1;
        }
    }
    sums.into_iter()
        .map(|(s, n)| s.map(|v| v / n.max(1) as f64))
        .collect()
}

/// Compares `img` with `reference` channel by channel.
pub fn compare(img: &Image, reference: &Image) -> Result<Metrics, EvalError> {
    compare_where(img, reference, None)
}

/// [`compare`] over the pixels `mask` keeps (all if `None`; row-major, one flag a pixel); the
/// region error stays over the whole image.
pub fn compare_where(
    img: &Image,
    reference: &Image,
    mask: Option<&[bool]>,
) -> Result<Metrics, EvalError> {
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
    let kept = |i: usize| mask.is_none_or(|m| m.get(i).copied().unwrap_or(false));
    let mut count = 0usize;
    let mut pixel_rel = Vec::new();
    for (_, (p, r)) in img
        .pixels
        .iter()
        .zip(&reference.pixels)
        .enumerate()
        .filter(|(i, _)| kept(*i))
    {
        count += 1;
        let rel_before = rel;
        for (x, r) in p.to_array().into_iter().zip(r.to_array()) {
            let (x, r) = (x as f64, r as f64);
            let d = x - r;
            se += d * d;
            rel += d * d / (r * r + 0.01);
            ae += d.abs();
            sum += x;
            ref_sum += r;
        }
        pixel_rel.push(rel - rel_before);
    }
    let n = (count * 3).max(1) as f64;
    let (mut region_diff, mut region_ref) = (0.0f64, 0.0f64);
    for (m, r) in region_means(img).iter().zip(region_means(reference)) {
        for (m, r) in m.iter().zip(r) {
            region_diff += (m - r).abs();
            region_ref += r.abs();
        }
    }
    Ok(Metrics {
        mse: se / n,
        rel_mse: rel / n,
        mae: ae / n,
        mean: sum / n,
        ref_mean: ref_sum / n,
        region_error: if region_ref > 0.0 {
            region_diff / region_ref
        } else {
            region_diff
        },
        worst_share: worst_share(pixel_rel),
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
        // Only the second pixel: squared errors 0, 0.25, 0.
        let m = compare_where(&x, &r, Some(&[false, true])).expect("same size");
        assert!((m.mse - 0.25 / 3.0).abs() < 1e-12 && (m.mae - 0.5 / 3.0).abs() < 1e-12);
        assert!((m.mean - 0.5 / 3.0).abs() < 1e-12 && m.ref_mean == 0.0);
    }

    #[test]
    fn the_worst_hundredth_s_share_of_the_relative_error() {
        // 250 pixels: 3 rounded up to the worst hundredth. Spread evenly: 3 / 250.
        let reference = Image::new(250, 1);
        let mut even = Image::new(250, 1);
        (0..250).for_each(|x| even.set(x, 0, Rgb::splat(0.1)));
        let m = compare(&even, &reference).expect("same size");
        assert!(
            (m.worst_share - 3.0 / 250.0).abs() < 1e-12,
            "{}",
            m.worst_share
        );
        // Three pixels off by 1 on black (1 / 0.01 a channel), the others by 0.1 (0.1^2 /
        // 0.01, 1 but for 0.1's rounding to f32): 300 / (300 + 247).
        [7, 100, 249].iter().for_each(|&x| even.set(x, 0, Rgb::ONE));
        let m = compare(&even, &reference).expect("same size");
        let want = 300.0 / (300.0 + 247.0);
        assert!(
            (m.worst_share - want).abs() < 1e-6,
            "{} vs {want}",
            m.worst_share
        );
        assert_eq!(
            compare(&reference, &reference).expect("same").worst_share,
            0.0
        );
    }

    #[test]
    fn region_error_sees_a_shifted_region_and_not_noise_within_one() {
        // A 16 x 16 reference of 1, so each of the 8 x 8 regions is 2 x 2 pixels.
        let mut reference = Image::new(16, 16);
        reference.pixels.fill(Rgb::ONE);
        // Noise that cancels within every region: no regional error, but an MSE.
        let mut noisy = reference.clone();
        for (i, p) in noisy.pixels.iter_mut().enumerate() {
            *p = Rgb::splat(if (i + i / 16) % 2 == 0 { 1.5 } else { 0.5 });
        }
        let m = compare(&noisy, &reference).expect("same size");
        assert!(m.region_error < 1e-12 && m.mse > 0.2, "{m:?}");
        // One region twice as bright: 1 of 64 regions off by 100%.
        let mut shifted = reference.clone();
        for (x, y) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            shifted.set(x, y, Rgb::splat(2.0));
        }
        let m = compare(&shifted, &reference).expect("same size");
        assert!((m.region_error - 1.0 / 64.0).abs() < 1e-12, "{m:?}");
    }
}
