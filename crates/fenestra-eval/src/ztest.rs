//! The per-pixel z-test Mitsuba 3 uses to show a render is unbiased: every pixel's difference
//! from a reference, divided by the standard error of that difference, must be consistent
//! with chance at significance alpha after Sidak correction for the number of pixels.

use crate::EvalError;
use fenestra_core::image::{Estimate, Image};
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, Normal};

/// The outcome of a z-test.
#[derive(Clone, Debug, Serialize)]
pub struct ZTest {
    /// Pixel-channel values tested.
    pub tests: usize,
    /// How many fell below the corrected per-value significance.
    pub failing: usize,
    /// Per-value significance after Sidak correction: 1 - (1 - alpha)^(1/tests).
    pub alpha_per_test: f64,
    /// Smallest two-sided p-value and where it occurred (x, y, channel).
    pub min_p: f64,
    /// Where the smallest p-value occurred: (x, y, channel).
    pub worst: (usize, usize, usize),
    /// Whether no value failed.
    pub passed: bool,
}

/// Tests `img` (with per-pixel variance of its mean `var`) against `reference` (with its own
/// variance `ref_var`, or exact if `None`), after averaging `block` x `block` pixels (which
/// makes variance estimates of heavy-tailed estimators trustworthy).
pub fn z_test(
    img: &Image,
    var: &Image,
    reference: &Image,
    ref_var: Option<&Image>,
    alpha: f64,
    block: usize,
) -> Result<ZTest, EvalError> {
    for other in [Some(var), Some(reference), ref_var].into_iter().flatten() {
        if (other.width, other.height) != (img.width, img.height) {
            return Err(EvalError::SizeMismatch(
                img.width,
                img.height,
                other.width,
                other.height,
            ));
        }
    }
    if !(alpha > 0.0 && alpha < 1.0) {
        return Err(EvalError::Parameter(format!(
            "alpha (the significance) must lie strictly between 0 and 1, not {alpha}"
        )));
    }
    if block == 0 || img.width / block == 0 || img.height / block == 0 {
        return Err(EvalError::Parameter(format!(
            "region: no {block}x{block}-pixel region fits in a {}x{} image",
            img.width, img.height
        )));
    }
    let (bw, bh) = (img.width / block, img.height / block);
    let normal = Normal::standard();
    let tests = bw * bh * 3;
    let alpha_per_test = 1.0 - (1.0 - alpha).powf(1.0 / tests.max(1) as f64);
    let mut out = ZTest {
        tests,
        failing: 0,
        alpha_per_test,
        min_p: 1.0,
        worst: (0, 0, 0),
        passed: true,
    };
    // Mean of a block and the variance of that mean, per channel.
    let block_stats = |im: &Image, bx: usize, by: usize, square: f64| -> [f64; 3] {
        let mut acc = [0.0f64; 3];
        for y in by * block..(by + 1) * block {
            for x in bx * block..(bx + 1) * block {
                for (a, v) in acc.iter_mut().zip(im.get(x, y).to_array()) {
                    *a += v as f64;
                }
            }
        }
        acc.map(|a| a / square)
    };
    let (n, n2) = (
        (block * block) as f64,
        (block * block * block * block) as f64,
    );
    for by in 0..bh {
        for bx in 0..bw {
            let x = block_stats(img, bx, by, n);
            let v = block_stats(var, bx, by, n2);
            let r = block_stats(reference, bx, by, n);
            let vr = ref_var.map_or([0.0; 3], |rv| block_stats(rv, bx, by, n2));
            for c in 0..3 {
                let sd = (v[c] + vr[c]).sqrt();
                let diff = x[c] - r[c];
                let p = if sd > 0.0 {
                    2.0 * (1.0 - normal.cdf((diff / sd).abs()))
                } else if diff.abs() <= 1e-6 * r[c].abs().max(1e-6) {
                    1.0
                } else {
                    0.0
                };
                if p < out.min_p {
                    out.min_p = p;
                    out.worst = (bx * block, by * block, c);
                }
                if p < alpha_per_test {
                    out.failing += 1;
                }
            }
        }
    }
    out.passed = out.failing == 0;
    Ok(out)
}

/// Two estimates of the same image compared over the whole image and over square regions.
#[derive(Clone, Debug, Serialize)]
pub struct Agreement {
    /// The z-test of blocks as large as the image's shorter side (the whole image when square).
    pub whole: ZTest,
    /// The z-test of `region` x `region` blocks.
    pub regions: ZTest,
}

impl Agreement {
    /// Whether both tests pass.
    pub fn passed(&self) -> bool {
        self.whole.passed && self.regions.passed
    }
}

/// Whether two estimators of the same image agree within their standard errors: `a` and `b`
/// (mean images with the per-pixel variances of their means) are compared by the z-test at
/// significance `alpha` over the whole image and over `region` x `region` blocks (block
/// means are close to normal even for heavy-tailed estimators).
pub fn agreement(
    a: &Estimate,
    b: &Estimate,
    alpha: f64,
    region: usize,
) -> Result<Agreement, EvalError> {
    let whole = a.mean.width.min(a.mean.height);
    let test = |block| {
        z_test(
            &a.mean,
            &a.variance,
            &b.mean,
            Some(&b.variance),
            alpha,
            block,
        )
    };
    Ok(Agreement {
        whole: test(whole)?,
        regions: test(region)?,
    })
}

/// How far one estimate's image mean lies from another's: a bias spread thinly over the
/// whole image, which no block's z-test sees, shows here.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct MeanShift {
    /// (mean of `b` - mean of `a`) / mean of `a`, over every pixel and channel.
    pub relative: f64,
    /// Standard error of `relative` (pixels independent: their variances of the mean add).
    pub standard_error: f64,
}

impl MeanShift {
    /// `relative` in standard errors.
    pub fn z(&self) -> f64 {
        self.relative / self.standard_error
    }
}

/// The relative shift of `b`'s image mean from `a`'s, with its standard error.
pub fn mean_shift(a: &Estimate, b: &Estimate) -> Result<MeanShift, EvalError> {
    for other in [&a.variance, &b.mean, &b.variance] {
        if (other.width, other.height) != (a.mean.width, a.mean.height) {
            return Err(EvalError::SizeMismatch(
                a.mean.width,
                a.mean.height,
                other.width,
                other.height,
            ));
        }
    }
    let sum = |im: &Image| -> f64 {
        im.pixels
            .iter()
            .flat_map(|p| p.to_array())
            .map(f64::from)
            .sum()
    };
    let mean_a = sum(&a.mean);
    Ok(MeanShift {
        relative: (sum(&b.mean) - mean_a) / mean_a,
        standard_error: (sum(&a.variance) + sum(&b.variance)).sqrt() / mean_a.abs(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Rgb;

    fn noisy(mean: f32, sd: f32, seed: u32) -> (Image, Image) {
        let mut img = Image::new(32, 32);
        let mut var = Image::new(32, 32);
        for (i, (p, v)) in img.pixels.iter_mut().zip(var.pixels.iter_mut()).enumerate() {
            // Sum of 12 uniforms minus 6: approximately standard normal.
            let g = |k: u32| {
                (0..12)
                    .map(|j| {
                        let key = (i as u32).wrapping_mul(97).wrapping_add(k * 13 + j);
                        fenestra_core::sampler::hash_combine(seed, key) as f32 / u32::MAX as f32
                    })
                    .sum::<f32>()
                    - 6.0
            };
            *p = Rgb::new(mean + sd * g(0), mean + sd * g(1), mean + sd * g(2));
            *v = Rgb::splat(sd * sd);
        }
        (img, var)
    }

    #[test]
    fn unbiased_noise_passes_and_a_shift_fails() {
        let reference = {
            let mut r = Image::new(32, 32);
            r.pixels.iter_mut().for_each(|p| *p = Rgb::splat(1.0));
            r
        };
        let (img, var) = noisy(1.0, 0.1, 1);
        let t = z_test(&img, &var, &reference, None, 0.01, 1).expect("sizes");
        assert!(t.passed, "{t:?}");
        assert_eq!(t.tests, 32 * 32 * 3);
        // A 5% bias is 0.5 standard errors per pixel, invisible pixel by pixel, but blocks of
        // 8x8 pixels shrink the standard error 8x and expose it.
        let (biased, var) = noisy(1.05, 0.1, 2);
        assert!(
            !z_test(&biased, &var, &reference, None, 0.01, 8)
                .expect("sizes")
                .passed
        );
        let (biased, var) = noisy(1.5, 0.1, 3);
        assert!(
            !z_test(&biased, &var, &reference, None, 0.01, 1)
                .expect("sizes")
                .passed
        );
    }

    #[test]
    fn a_shift_of_the_mean_is_measured_with_its_standard_error() {
        let estimate = |(mean, variance)| Estimate { mean, variance };
        let a = estimate(noisy(1.0, 0.1, 6));
        let same = mean_shift(&a, &estimate(noisy(1.0, 0.1, 7))).expect("sizes");
        // 3,072 values of sd 0.1 each side: the shift's standard error is 0.1 sqrt(2 / 3072).
        let se = 0.1 * (2.0f64 / 3072.0).sqrt();
        assert!((same.standard_error / se - 1.0).abs() < 1e-3, "{same:?}");
        assert!(same.z().abs() < 4.0, "{same:?}");
        // A 1% shift, 0.4 standard errors a pixel, is 3.9 standard errors of the mean.
        let shifted = mean_shift(&a, &estimate(noisy(1.01, 0.1, 7))).expect("sizes");
        assert!(
            (shifted.relative - same.relative - 0.01).abs() < 1e-4,
            "{shifted:?}"
        );
        let small = Estimate {
            mean: Image::new(8, 8),
            variance: Image::new(8, 8),
        };
        assert!(mean_shift(&a, &small).is_err());
    }

    #[test]
    fn agreement_needs_both_estimates_to_match_everywhere() {
        let estimate = |(mean, variance)| Estimate { mean, variance };
        let a = estimate(noisy(1.0, 0.1, 4));
        let t = agreement(&a, &estimate(noisy(1.0, 0.1, 5)), 0.01, 8).expect("sizes");
        assert!(t.passed(), "{t:?}");
        assert_eq!((t.whole.tests, t.regions.tests), (3, 16 * 3));
        // A 2% shift is 1.1 standard errors of an 8x8 region's difference, within chance, but
        // 4.5 of the whole image's.
        let t = agreement(&a, &estimate(noisy(1.02, 0.1, 6)), 0.01, 8).expect("sizes");
        assert!(t.regions.passed && !t.whole.passed, "{t:?}");
    }

    /// A significance of NaN, 2 or 0 made a 50% brighter image "agree" (issue 68 item 14).
    #[test]
    fn a_significance_outside_0_1_and_empty_regions_are_refused() {
        let estimate = |(mean, variance)| Estimate { mean, variance };
        let a = estimate(noisy(1.0, 0.1, 4));
        let brighter = estimate(noisy(1.5, 0.1, 5));
        assert!(!agreement(&a, &brighter, 0.01, 8).expect("test").passed());
        for alpha in [f64::NAN, 2.0, -1.0, 0.0, 1.0] {
            let e = agreement(&a, &brighter, alpha, 8)
                .expect_err("alpha")
                .to_string();
            assert!(
                e.starts_with("alpha (the significance) must lie strictly between 0 and 1"),
                "{e}"
            );
        }
        for region in [0, 10_000] {
            let e = agreement(&a, &brighter, 0.01, region)
                .expect_err("region")
                .to_string();
            assert!(
                e.starts_with(&format!("region: no {region}x{region}-pixel region fits")),
                "{e}"
            );
        }
    }
}
