//! The orthonormal Haar wavelet transform W of seed 003 §4.5.1 on vectors of length 2^n
//! (transfer vectors are padded with zeros to the next power of two, which keeps W
//! orthonormal on the padded space): <Wx, Wy> = <x, y>, so distances to affine subspaces,
//! and with them LPCA's assignments and subspaces, are the same for the vectors and their
//! wavelet images (eq. 4.3-4.4 and the proof after Alg. 4).
//!
//! Layout (the standard pyramid): index 0 holds the overall scaling coefficient, indices
//! [2^k, 2^(k+1)) the details of level k (coarsest k = 0), detail i of level k covering the
//! block [i n / 2^k, (i + 1) n / 2^k) of the signal.

use std::f64::consts::FRAC_1_SQRT_2;

/// The padded length for vectors of dimension `d`.
pub fn padded_len(d: usize) -> usize {
    d.max(1).next_power_of_two()
}

/// Forward transform in place (`x.len()` a power of two); `scratch` of the same length.
pub fn forward(x: &mut [f64], scratch: &mut [f64]) {
    let n = x.len();
    assert!(n.is_power_of_two(), "Haar transform of length {n}");
    let mut len = n;
    while len > 1 {
        let half = len / 2;
        for i in 0..half {
            let (a, b) = (x[2 * i], x[2 * i + 1]);
            scratch[i] = (a + b) * FRAC_1_SQRT_2;
            scratch[half + i] = (a - b) * FRAC_1_SQRT_2;
        }
        x[..len].copy_from_slice(&scratch[..len]);
        len = half;
    }
}

/// Inverse transform in place.
pub fn inverse(x: &mut [f64], scratch: &mut [f64]) {
    let n = x.len();
    assert!(n.is_power_of_two(), "Haar transform of length {n}");
    let mut len = 2;
    while len <= n {
        let half = len / 2;
        for i in 0..half {
            let (s, d) = (x[i], x[half + i]);
            scratch[2 * i] = (s + d) * FRAC_1_SQRT_2;
            scratch[2 * i + 1] = (s - d) * FRAC_1_SQRT_2;
        }
        x[..len].copy_from_slice(&scratch[..len]);
        len *= 2;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Sampler;

    fn signal(n: usize, seed: u64) -> Vec<f64> {
        let mut s = Sampler::new(seed, 0, 0);
        (0..n).map(|_| s.next_1d() as f64 * 2.0 - 1.0).collect()
    }

    #[test]
    fn the_transform_round_trips_and_keeps_dot_products() {
        for n in [1usize, 2, 8, 64, 1024] {
            let (x, y) = (signal(n, 1), signal(n, 2));
            let (mut wx, mut wy, mut scratch) = (x.clone(), y.clone(), vec![0.0; n]);
            forward(&mut wx, &mut scratch);
            forward(&mut wy, &mut scratch);
            let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(p, q)| p * q).sum::<f64>();
            assert!((dot(&x, &y) - dot(&wx, &wy)).abs() < 1e-9 * n as f64);
            assert!((dot(&x, &x) - dot(&wx, &wx)).abs() < 1e-9 * n as f64);
            let mut back = wx.clone();
            inverse(&mut back, &mut scratch);
            for (a, b) in x.iter().zip(&back) {
                assert!((a - b).abs() < 1e-12, "n {n}: {a} vs {b}");
            }
        }
    }
}
