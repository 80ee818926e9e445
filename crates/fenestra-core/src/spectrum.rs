//! Spectra to colour: the CIE 1931 2-degree observer (the analytic multi-lobe fit of Wyman,
//! Sloan and Shirley 2013, JCGT 2(2)) and CIE XYZ to linear sRGB (D65).

fn lobe(l: f64, mu: f64, s1: f64, s2: f64) -> f64 {
    let s = if l < mu { s1 } else { s2 };
    (-0.5 * ((l - mu) / s).powi(2)).exp()
}

/// CIE 1931 2-degree colour matching functions at wavelength `l` (nm), Wyman et al. 2013
/// (y-bar peaks at 1, so the integral of a spectral radiance against it, in W/(m^2 sr), is
/// the luminance over 683 lm/W).
pub fn cie_xyz(l: f64) -> [f64; 3] {
    [
        1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7)
            - 0.065 * lobe(l, 501.1, 20.4, 26.2),
        0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1),
        1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8),
    ]
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
