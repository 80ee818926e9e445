//! Sines, cosines and arc cosines by the minimax polynomials of Cephes' single-precision
//! functions (within a few ulps on the ranges sampling needs): several times faster than
//! the C library's, whose argument reduction serves every angle, and the same on every
//! machine (glibc picks its own code by CPU features at run time). The arc cosine takes
//! four arguments at once (the spherical rectangle needs four).

use glam::Vec4;
use std::f32::consts::{FRAC_2_PI, FRAC_PI_2, PI};

/// sin and cos of `x` in [-pi/4, pi/4] (a little beyond stays accurate).
pub fn sin_cos_quarter(x: f32) -> (f32, f32) {
    let x2 = x * x;
    let sin = x + x * x2 * (-1.666_665_5e-1 + x2 * (8.332_161e-3 + x2 * -1.951_529_6e-4));
    let cos =
        1.0 - 0.5 * x2 + x2 * x2 * (4.166_664_6e-2 + x2 * (-1.388_731_6e-3 + x2 * 2.443_315_7e-5));
    (sin, cos)
}

/// sin and cos of `x`, for angles of a few turns at most (|x| below about 1e3; beyond,
/// the reduction to a quarter turn loses accuracy).
pub fn sin_cos(x: f32) -> (f32, f32) {
    // The nearest multiple q of pi/2, and x - q pi/2 in three parts (Cody and Waite): the
    // first part has few bits, so q times it is exact.
    let q = (x * FRAC_2_PI + 0.5f32.copysign(x)) as i32;
    let qf = q as f32;
    let r = ((x - qf * 1.570_312_5) - qf * 4.837_513e-4) - qf * 7.549_79e-8;
    let (s, c) = sin_cos_quarter(r);
    match q & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// Cephes' asinf polynomial: asin(t) = t + t z p(z) with z = t^2, |t| <= 1/2.
fn asin_poly(z: Vec4) -> Vec4 {
    (((z * 4.216_32e-2 + 2.418_131e-2) * z + 4.547_002_6e-2) * z + 7.495_300_3e-2) * z
        + 1.666_675_2e-1
}

/// The arc cosines of four values in [-1, 1] (clamped), in [0, pi], with four-wide
/// arithmetic.
pub fn acos4(x: Vec4) -> Vec4 {
    let x = x.clamp(Vec4::splat(-1.0), Vec4::ONE);
    let a = x.abs();
    // Near |x| = 1, acos(a) = 2 asin(sqrt((1 - a) / 2)), with 1 - a exact.
    let big = a.cmpgt(Vec4::splat(0.5));
    let z = Vec4::select(big, 0.5 * (Vec4::ONE - a), a * a);
    let t = Vec4::select(big, z.sqrt(), a);
    let r = t + t * z * asin_poly(z);
    let negative = x.cmplt(Vec4::ZERO);
    let small = Vec4::select(negative, FRAC_PI_2 + r, FRAC_PI_2 - r);
    let large = Vec4::select(negative, PI - 2.0 * r, 2.0 * r);
    Vec4::select(big, large, small)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance from `x` to the next f32 away from zero.
    fn ulp(x: f32) -> f64 {
        (f32::from_bits(x.abs().to_bits() + 1) - x.abs()) as f64
    }

    #[test]
    fn quarter_sin_cos_is_within_two_ulps() {
        let n = 100_000;
        for i in 0..=n {
            let x = (i as f32 / n as f32 * 2.0 - 1.0) * 0.25 * PI;
            let (sin, cos) = sin_cos_quarter(x);
            let (s64, c64) = (x as f64).sin_cos();
            // Near zero sin's ulp shrinks with it; x's own rounding bounds the error there.
            let tol = 2.0 * ulp(s64 as f32).max(ulp(x));
            assert!(
                (sin as f64 - s64).abs() <= tol,
                "sin {x}: {sin} against {s64}"
            );
            let tol = 2.0 * ulp(c64 as f32);
            assert!(
                (cos as f64 - c64).abs() <= tol,
                "cos {x}: {cos} against {c64}"
            );
        }
    }

    #[test]
    fn sin_cos_of_a_few_turns_is_within_a_few_ulps_of_one() {
        // Angles up to 3 turns either way: the absolute error stays within 3 ulps of 1.
        let n = 200_000;
        let mut worst = 0.0f64;
        for i in 0..=n {
            let x = (i as f32 / n as f32 * 2.0 - 1.0) * 6.0 * PI;
            let (sin, cos) = sin_cos(x);
            let (s64, c64) = (x as f64).sin_cos();
            worst = worst
                .max((sin as f64 - s64).abs())
                .max((cos as f64 - c64).abs());
        }
        assert!(worst <= 3.0 * ulp(1.0), "worst absolute error {worst:e}");
    }

    #[test]
    fn acos4_is_within_three_ulps_in_every_lane() {
        let close = |x: f32, y: f32| {
            let exact = (x.clamp(-1.0, 1.0) as f64).acos();
            (y as f64 - exact).abs() <= 3.0 * ulp(exact as f32)
        };
        let n = 200_000;
        for i in 0..=n {
            let x = i as f32 / n as f32 * 2.0 - 1.0;
            let lanes = [x, -x, x * 0.5, 1.0];
            let four = acos4(Vec4::from_array(lanes)).to_array();
            for (x, y) in lanes.into_iter().zip(four) {
                assert!(close(x, y), "acos {x}: {y}");
            }
        }
        // Just inside both ends, where 1 - |x| is tiny, and beyond them (clamped).
        let ends = Vec4::new(1.0 - 6e-8, -1.0 + 6e-8, 0.5, -0.5);
        for (x, y) in ends.to_array().into_iter().zip(acos4(ends).to_array()) {
            assert!(close(x, y), "acos {x}: {y}");
        }
        assert_eq!(
            acos4(Vec4::new(1.5, -1.5, 0.0, 1.0)).to_array(),
            [0.0, PI, FRAC_PI_2, 0.0]
        );
    }
}
