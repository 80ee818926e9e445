//! A film's white balance as pbrt-v4 applies it (Film "whitebalance" with its CIE 1931
//! sensor): the white of an illuminant at a colour temperature (CIE daylight, or a Planckian
//! radiator below 4000 K) is adapted to the image's white, sRGB's D65, by von Kries scaling
//! of Bradford's cone responses.

use crate::spectrum::{cie_xyz, xyz_to_linear_srgb};
use glam::{DMat3, DVec3, Mat3};

/// The white of sRGB, CIE D65's chromaticity.
pub const D65: [f64; 2] = [0.3127, 0.3290];

/// Bradford's cone responses from XYZ (Lam 1985), row by row.
const BRADFORD: [[f64; 3]; 3] = [
    [0.8951, 0.2664, -0.1614],
    [-0.7502, 1.7135, 0.0367],
    [0.0389, -0.0685, 1.0296],
];

/// A matrix given row by row.
fn rows(m: [[f64; 3]; 3]) -> DMat3 {
    DMat3::from_cols_array_2d(&m).transpose()
}

/// CIE daylight's chromaticity at correlated colour temperature `cct` (K; CIE 15, defined
/// from 4000 to 25000 K).
pub fn daylight_xy(cct: f64) -> [f64; 2] {
    let (t, t2, t3) = (cct, cct * cct, cct * cct * cct);
    let x = if cct <= 7000.0 {
        -4.6070e9 / t3 + 2.9678e6 / t2 + 0.09911e3 / t + 0.244063
    } else {
        -2.0064e9 / t3 + 1.9018e6 / t2 + 0.24748e3 / t + 0.237040
    };
    [x, -3.0 * x * x + 2.870 * x - 0.275]
}

/// A Planckian radiator's chromaticity at `kelvin`: Planck's law integrated against the CIE
/// 1931 tables at 1 nm, as pbrt-v4 takes the white of a blackbody. (Kim et al.'s cubic fit of
/// the locus, used before, is within 2e-4 of it: enough to leave a balanced red 0.6% off.)
pub fn planckian_xy(kelvin: f64) -> [f64; 2] {
    let (h, c, k) = (6.626_070_15e-34, 299_792_458.0, 1.380_649e-23);
    let mut xyz = [0.0f64; 3];
    for i in 0..=470 {
        let l = (360 + i) as f64 * 1e-9;
        let radiance = 1.0 / (l.powi(5) * ((h * c / (l * k * kelvin)).exp() - 1.0));
        for (s, b) in xyz.iter_mut().zip(cie_xyz(360.0 + i as f64)) {
            *s += b * radiance;
        }
    }
    let sum = xyz[0] + xyz[1] + xyz[2];
    [xyz[0] / sum, xyz[1] / sum]
}

/// The white of the illuminant pbrt-v4 takes for a film's `whitebalance` temperature: the
/// nominal temperature times 1.4388/1.4380 (the second radiation constant as revised in
/// 1968, as CIE daylight's nominal temperatures are), CIE daylight from 4000 K and a
/// Planckian radiator below.
pub fn illuminant_white(kelvin: f64) -> [f64; 2] {
    let cct = kelvin * 1.4388 / 1.4380;
    if cct < 4000.0 {
        planckian_xy(cct)
    } else {
        daylight_xy(cct)
    }
}

/// XYZ of chromaticity `xy` at luminance 1.
fn xyz_of([x, y]: [f64; 2]) -> DVec3 {
    DVec3::new(x / y, 1.0, (1.0 - x - y) / y)
}

/// The XYZ-to-XYZ adaptation that takes white `from` to white `to` (von Kries scaling of
/// Bradford's cone responses).
pub fn adaptation(from: [f64; 2], to: [f64; 2]) -> DMat3 {
    let lms = rows(BRADFORD);
    let (src, dst) = (lms * xyz_of(from), lms * xyz_of(to));
    lms.inverse() * DMat3::from_diagonal(dst / src) * lms
}

/// The white balance of a linear sRGB image for an illuminant of `kelvin`, as pbrt-v4's film
/// makes it with "whitebalance" `kelvin`: the illuminant's white becomes the image's white.
pub fn srgb_white_balance(kelvin: f32) -> Mat3 {
    let rows_of = |f: fn([f64; 3]) -> [f64; 3]| {
        DMat3::from_cols(
            DVec3::from(f([1.0, 0.0, 0.0])),
            DVec3::from(f([0.0, 1.0, 0.0])),
            DVec3::from(f([0.0, 0.0, 1.0])),
        )
    };
    let rgb_from_xyz = rows_of(xyz_to_linear_srgb);
    let m =
        rgb_from_xyz * adaptation(illuminant_white(kelvin as f64), D65) * rgb_from_xyz.inverse();
    m.as_mat3()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 2], b: [f64; 2], tol: f64) -> bool {
        (a[0] - b[0]).abs() <= tol && (a[1] - b[1]).abs() <= tol
    }

    #[test]
    fn daylight_and_planckian_whites_are_the_cie_ones() {
        // CIE 15's D50 and D65 (nominal 5000 and 6500 K) and illuminant A (2856 K).
        assert!(close(illuminant_white(6500.0), [0.31272, 0.32903], 2e-4));
        assert!(close(illuminant_white(5000.0), [0.34567, 0.35851], 2e-4));
        // Illuminant A: a Planckian radiator at 2856 K (CIE 15:2004, c2 = 1.4388e-2).
        assert!(close(planckian_xy(2856.0), [0.44757, 0.40745], 1e-4));
        // The locus' tabulated point (a CIE 1931 integral) at 3500 K.
        assert!(close(planckian_xy(3500.0), [0.40532, 0.39066], 1e-4));
        // Both sides of 4000 K meet (within the daylight locus' offset from Planck's).
        assert!(close(
            illuminant_white(3995.0),
            illuminant_white(3999.0),
            0.01
        ));
    }

    #[test]
    fn the_balance_turns_the_illuminant_white_grey_and_leaves_d65_alone() {
        for kelvin in [2700.0f32, 3500.0, 5000.0, 9000.0] {
            let m = srgb_white_balance(kelvin);
            let white = xyz_to_linear_srgb(xyz_of(illuminant_white(kelvin as f64)).into());
            let out = m * glam::Vec3::new(white[0] as f32, white[1] as f32, white[2] as f32);
            // Grey to the rounding of the 4-digit sRGB matrix, which takes D65 to
            // (0.99984, 1.00010, 1.00007).
            let spread = out.max_element() - out.min_element();
            assert!(spread < 5e-4 * out.max_element(), "{kelvin} K: {out}");
            // Luminance-preserving on the white: Y stays 1.
            assert!((out.dot(glam::Vec3::new(0.2126, 0.7152, 0.0722)) - 1.0).abs() < 2e-3);
        }
        // 6500 K is D65 (to the rounding of the daylight formula): nearly the identity.
        let m = srgb_white_balance(6500.0);
        assert!(m.abs_diff_eq(Mat3::IDENTITY, 2e-3), "{m}");
        // A warm light balanced: blue gains on red.
        let warm = srgb_white_balance(3000.0) * glam::Vec3::ONE;
        assert!(warm.z > 1.5 * warm.x, "{warm}");
    }
}
