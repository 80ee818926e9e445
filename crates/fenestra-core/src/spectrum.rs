//! Spectra to colour: the CIE 1931 2-degree observer (the CIE's 1 nm tables, as pbrt-v4 uses
//! them) and CIE XYZ to linear sRGB (D65).

use crate::cie1931::CIE_1931_2DEG;

/// CIE 1931 2-degree colour matching functions at wavelength `l` (nm): the CIE's table,
/// linear between its 1 nm samples, 0 outside 360-830 nm (y-bar peaks at 1, so the integral
/// of a spectral radiance against it, in W/(m^2 sr), is the luminance over 683 lm/W). An
/// analytic fit (Wyman et al. 2013) stood here before: its colours of blackbody lights were
/// up to 0.7% off pbrt-v4's in a channel.
pub fn cie_xyz(l: f64) -> [f64; 3] {
    let t = l - 360.0;
    if !(0.0..=470.0).contains(&t) {
        return [0.0; 3];
    }
    let i = (t as usize).min(469);
    let f = t - i as f64;
    let (a, b) = (CIE_1931_2DEG[i], CIE_1931_2DEG[i + 1]);
    std::array::from_fn(|k| a[k] + (b[k] - a[k]) * f)
}

/// CIE XYZ to linear sRGB (D65 white).
pub fn xyz_to_linear_srgb([x, y, z]: [f64; 3]) -> [f64; 3] {
    [
        3.2406 * x - 1.5372 * y - 0.4986 * z,
        -0.9689 * x + 1.8758 * y + 0.0415 * z,
        0.0557 * x - 0.2040 * y + 1.0570 * z,
    ]
}

/// Linear sRGB of `s` (a function of wavelength in nm) integrated against the observer from
/// 360 to 830 nm in 1 nm steps, unnormalised: a spectral radiance in W/(m^2 sr nm) gives
/// an RGB whose luminance is the photometric luminance over 683 lm/W.
pub fn spectrum_to_linear_srgb(s: impl Fn(f64) -> f64) -> [f64; 3] {
    let mut acc = [0.0; 3];
    for i in 0..=470 {
        let l = 360.0 + i as f64;
        let c = cie_xyz(l);
        let v = s(l);
        for k in 0..3 {
            acc[k] += c[k] * v;
        }
    }
    xyz_to_linear_srgb(acc)
}
