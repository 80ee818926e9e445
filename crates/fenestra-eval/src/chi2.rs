//! Pearson's chi-square goodness of fit: the one harness every sampler's test uses, as
//! pbrt-v4's and Mitsuba's (`mi.chi2`) do. Observed counts per bin are held against the counts
//! the sampler's density expects there; bins expecting fewer than [`MIN_EXPECTED`] are pooled
//! in increasing order of expectation (each pool closed once it expects that many), and the
//! p-value comes from the chi-square distribution of (bins - 1) degrees of freedom.

use statrs::distribution::{ChiSquared, ContinuousCDF};

/// The fewest samples a bin (or pool of bins) must expect to take part on its own.
pub const MIN_EXPECTED: f64 = 5.0;

/// Below this many expected samples a bin expects nothing (a density that is zero there).
const NOTHING: f64 = 1e-6;

/// The outcome of a test.
#[derive(Clone, Copy, Debug)]
pub struct Chi2 {
    /// Pearson's statistic.
    pub statistic: f64,
    /// Degrees of freedom: bins after pooling, less one.
    pub dof: usize,
    /// The probability of a statistic at least this large if the density is right.
    pub p_value: f64,
}

/// Why the counts cannot fit the density whatever the statistic.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum Chi2Error {
    /// Counts and expectations are not over the same bins.
    #[error("{observed} bins of counts against {expected} bins of expectations")]
    Bins {
        /// Bins of counts.
        observed: usize,
        /// Bins of expectations.
        expected: usize,
    },
    /// Samples landed where the density is zero.
    #[error("{observed} samples in bin {bin}, where the density expects none")]
    Stray {
        /// The bin.
        bin: usize,
        /// Its count.
        observed: f64,
    },
}

/// Tests `observed` counts against `expected` counts over the same bins. A bin that expects
/// nothing may hold up to `stray` samples (a sliver of density a midpoint rule misses); more
/// is an error, whatever the statistic.
pub fn chi2(observed: &[f64], expected: &[f64], stray: f64) -> Result<Chi2, Chi2Error> {
    if observed.len() != expected.len() {
        return Err(Chi2Error::Bins {
            observed: observed.len(),
            expected: expected.len(),
        });
    }
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut statistic, mut bins) = (0.0f64, 0usize);
    let mut term = |o: f64, e: f64| {
        statistic += (o - e).powi(2) / e;
        bins += 1;
    };
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    for &i in &order {
        let (o, e) = (observed[i], expected[i]);
        if e < NOTHING {
            if o > stray {
                return Err(Chi2Error::Stray {
                    bin: i,
                    observed: o,
                });
            }
        } else if e < MIN_EXPECTED {
            (pool_o, pool_e) = (pool_o + o, pool_e + e);
            if pool_e >= MIN_EXPECTED {
                term(pool_o, pool_e);
                (pool_o, pool_e) = (0.0, 0.0);
            }
        } else {
            term(o, e);
        }
    }
    if pool_e > 0.0 {
        term(pool_o, pool_e);
    }
    let dof = bins.saturating_sub(1).max(1);
    let p_value = ChiSquared::new(dof as f64).map_or(0.0, |d| 1.0 - d.cdf(statistic));
    Ok(Chi2 {
        statistic,
        dof,
        p_value,
    })
}

/// The significance each of `tests` tests must pass for all of them together to fail at
/// `alpha` when every density is right (Šidák's correction).
pub fn sidak(alpha: f64, tests: usize) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / tests as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Rng;

    /// Counts of `n` draws of `draw` over `bins` equal bins of [0, 1).
    fn counts(n: usize, bins: usize, mut draw: impl FnMut(&mut Rng) -> f32) -> Vec<f64> {
        let mut rng = Rng::new(11);
        let mut c = vec![0.0; bins];
        for _ in 0..n {
            c[((draw(&mut rng) * bins as f32) as usize).min(bins - 1)] += 1.0;
        }
        c
    }

    #[test]
    fn a_right_density_passes_and_a_slightly_wrong_one_fails() {
        let (n, bins) = (200_000, 50);
        // Density 2x on [0, 1): sampled by the square root of a uniform number.
        let linear: Vec<f64> = (0..bins)
            .map(|b| n as f64 * ((b + 1) * (b + 1) - b * b) as f64 / (bins * bins) as f64)
            .collect();
        let right = counts(n, bins, |r| r.next_f32().sqrt());
        let fit = chi2(&right, &linear, 0.0).expect("same bins");
        assert!(fit.p_value > 1e-3, "{fit:?}");
        assert_eq!(fit.dof, bins - 1);
        // A few percent too much density near 1.
        let wrong = counts(n, bins, |r| r.next_f32().powf(0.47));
        let fit = chi2(&wrong, &linear, 0.0).expect("same bins");
        assert!(fit.p_value < 1e-6, "{fit:?}");
    }

    #[test]
    fn sparse_bins_are_pooled_and_strays_refused() {
        // Ten bins expecting 1 each pool into two of 5; one bin expecting 90.
        let mut expected = vec![1.0; 10];
        expected.push(90.0);
        let mut observed = expected.clone();
        let fit = chi2(&observed, &expected, 0.0).expect("fits");
        assert_eq!((fit.statistic, fit.dof), (0.0, 2));
        expected.push(0.0);
        observed.push(3.0);
        assert_eq!(
            chi2(&observed, &expected, 2.0).expect_err("strays"),
            Chi2Error::Stray {
                bin: 11,
                observed: 3.0
            }
        );
        assert!(chi2(&observed, &expected, 3.0).is_ok());
        assert!(matches!(
            chi2(&observed[..3], &expected, 0.0),
            Err(Chi2Error::Bins { .. })
        ));
        assert!((sidak(0.01, 1) - 0.01).abs() < 1e-12);
        assert!(sidak(0.01, 47) < 0.01 / 46.0);
    }
}
