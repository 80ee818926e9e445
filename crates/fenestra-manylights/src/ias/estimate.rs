//! A pixel's estimate in a pass and its variance (seed 004 §3.5.3, App. A.1).

use super::point::Point;
use fenestra_core::Rgb;

/// A point's samples in a pass: sums of the values and of their squares per channel.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PointSums {
    sum: [f64; 3],
    sq: [f64; 3],
    n: u32,
}

impl PointSums {
    pub(super) fn add(&mut self, v: Rgb) {
        for (c, x) in v.to_array().into_iter().enumerate() {
            self.sum[c] += f64::from(x);
            self.sq[c] += f64::from(x) * f64::from(x);
        }
        self.n += 1;
    }
}

pub(super) fn luminance(c: [f64; 3]) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// The seed's conservative estimate of the variance of a mean `m` of `n` samples whose
/// squares sum to `sum_sq` (App. A.1, eq. A.3): with V = sum x^2 / N^2 and
/// E = m / N - 3 sqrt(V) / N^2, s^2 = V if E < 0, else V - N E^2.
pub(super) fn conservative_variance(m: f64, sum_sq: f64, n: f64) -> f64 {
    let v = sum_sq / (n * n);
    let e = m / n - 3.0 * v.sqrt() / (n * n);
    if e < 0.0 {
        v
    } else {
        (v - n * e * e).max(0.0)
    }
}

/// The pixel's estimate for a pass, I = sum over points of area x mean, and the
/// conservative variance of its mean (App. A.1, eq. A.3) in luminance and per channel. As
/// pixel values, the N samples of the pass are x_i = value x area x N / n_point, so that
/// their mean is I.
pub(super) fn pass_estimate(points: &[Point], sums: &[PointSums]) -> ([f64; 3], f64, [f64; 3]) {
    let n: u32 = sums.iter().map(|s| s.n).sum();
    if n == 0 {
        return ([0.0; 3], 0.0, [0.0; 3]);
    }
    let big_n = f64::from(n);
    let (mut estimate, mut second) = ([0.0f64; 3], [0.0f64; 3]);
    for (q, s) in points.iter().zip(sums).filter(|(_, s)| s.n > 0) {
        let scale = f64::from(q.area) * big_n / f64::from(s.n);
        for c in 0..3 {
            estimate[c] += s.sum[c] * scale / big_n;
            second[c] += s.sq[c] * scale * scale;
        }
    }
    let conservative = |m: f64, sq: f64| conservative_variance(m, sq, big_n);
    let channels: [f64; 3] = std::array::from_fn(|c| conservative(estimate[c], second[c]));
    // The luminance's second moment needs the cross terms; its samples' squares are bounded
    // by the channels' (luminance is a convex combination), so this stays conservative.
    let lum_second = 0.2126 * second[0] + 0.7152 * second[1] + 0.0722 * second[2];
    (
        estimate,
        conservative(luminance(estimate), lum_second),
        channels,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_conservative_variance_is_at_least_the_plain_variance_of_the_mean() {
        // eq. A.3 against (1/N^2) sum (x - m)^2 for random sample sets, and above it by the
        // 3 sqrt(V) term where that matters: few samples.
        let mut rng = fenestra_core::Rng::new(8);
        for _ in 0..200 {
            let n = 2 + (rng.next_f32() * 60.0) as usize;
            let xs: Vec<f64> = (0..n).map(|_| f64::from(rng.next_f32()).powi(3)).collect();
            let big_n = n as f64;
            let m = xs.iter().sum::<f64>() / big_n;
            let unbiased =
                xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (big_n * (big_n - 1.0));
            let sum_sq = xs.iter().map(|x| x * x).sum::<f64>();
            let s2 = conservative_variance(m, sum_sq, big_n);
            let plain = unbiased * (big_n - 1.0) / big_n;
            assert!(s2 >= plain * (1.0 - 1e-9), "{s2} < {plain}");
            if n <= 4 && m > 0.0 {
                assert!(s2 > plain, "{n} samples: {s2} not above {plain}");
            }
        }
    }
}
