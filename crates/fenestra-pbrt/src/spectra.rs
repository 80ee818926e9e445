//! pbrt-v4 spectra turned into fenestra's linear sRGB: sampled spectra and blackbodies through
//! the CIE 1931 observer (`fenestra_core::spectrum`), and the named spectra pbrt-v4 ships, as
//! RGB values.

use fenestra_core::spectrum::spectrum_to_linear_srgb;
use fenestra_core::Rgb;

/// A spectrum-valued parameter as written.
#[derive(Clone, Debug, PartialEq)]
pub enum SpectrumParam {
    Rgb(Rgb),
    Blackbody(f32),
    /// (wavelength nm, value) pairs.
    Sampled(Vec<(f32, f32)>),
    /// A named spectrum ("metal-Au-eta", "glass-BK7", ...).
    Named(String),
}

/// RGB of a spectrum given as a function of wavelength, scaled per channel so that the
/// constant spectrum 1 maps to white (1, 1, 1).
fn spectrum_to_rgb(s: impl Fn(f64) -> f64) -> Rgb {
    let white = spectrum_to_linear_srgb(|_| 1.0);
    let c = spectrum_to_linear_srgb(s);
    Rgb::new(
        (c[0] / white[0]) as f32,
        (c[1] / white[1]) as f32,
        (c[2] / white[2]) as f32,
    )
}

/// `c` scaled to luminance 1 (black if it has none).
fn unit_luminance(c: Rgb) -> Rgb {
    let y = c.luminance();
    if y > 0.0 && y.is_finite() {
        c / y
    } else {
        Rgb::ZERO
    }
}

/// Planck's law: spectral radiance at wavelength `l` nm of a blackbody at `kelvin`.
fn planck(kelvin: f32) -> impl Fn(f64) -> f64 {
    let t = kelvin as f64;
    move |l: f64| {
        let lm = l * 1e-9;
        let (h, c, k) = (6.626_070_15e-34, 299_792_458.0, 1.380_649e-23);
        2.0 * h * c * c / (lm.powi(5) * ((h * c / (lm * k * t)).exp() - 1.0))
    }
}

/// Colour of a blackbody at `kelvin` as a reflectance-like value (the equal-energy spectrum
/// white), normalised to luminance 1.
pub fn blackbody(kelvin: f32) -> Rgb {
    unit_luminance(spectrum_to_rgb(planck(kelvin)))
}

/// The colour a light's spectrum has in pbrt-v4's image: its CIE 1931 XYZ in linear sRGB
/// with no white balance (so the equal-energy spectrum is pinkish and D65 white), normalised
/// to luminance 1, as pbrt-v4 divides every light's spectrum by its photometric luminance
/// (the light's scale or power sets its brightness). RGB and named spectra are taken as
/// written.
pub fn illuminant_to_rgb(s: &SpectrumParam) -> Result<Rgb, SpectrumError> {
    let xyz_rgb = |f: &dyn Fn(f64) -> f64| {
        let c = spectrum_to_linear_srgb(f);
        unit_luminance(Rgb::new(c[0] as f32, c[1] as f32, c[2] as f32))
    };
    match s {
        SpectrumParam::Blackbody(t) if *t > 0.0 => Ok(xyz_rgb(&planck(*t))),
        SpectrumParam::Sampled(p) if !p.is_empty() => Ok(xyz_rgb(&interpolated(p))),
        other => to_rgb(other),
    }
}

/// Piecewise-linear spectrum through (wavelength, value) pairs, 0 beyond its ends.
pub fn sampled(pairs: &[(f32, f32)]) -> Rgb {
    spectrum_to_rgb(interpolated(pairs))
}

/// The piecewise-linear function through (wavelength, value) pairs, 0 beyond its ends, as
/// pbrt-v4's PiecewiseLinearSpectrum (held constant beyond them before: an equal-energy light
/// given from 400 to 700 nm came out 0.9% bluer than pbrt-v4's).
fn interpolated(pairs: &[(f32, f32)]) -> impl Fn(f64) -> f64 {
    let mut p: Vec<(f64, f64)> = pairs.iter().map(|&(l, v)| (l as f64, v as f64)).collect();
    p.sort_by(|a, b| a.0.total_cmp(&b.0));
    move |l: f64| {
        let i = p.partition_point(|q| q.0 < l);
        if l < p[0].0 || l > p[p.len() - 1].0 {
            0.0
        } else if i == 0 {
            p[0].1
        } else {
            let (a, b) = (p[i - 1], p[i]);
            let t = if b.0 > a.0 {
                (l - a.0) / (b.0 - a.0)
            } else {
                0.0
            };
            a.1 + t * (b.1 - a.1)
        }
    }
}

/// Named spectra of pbrt-v4 as RGB: metal indices (eta, k) at the sRGB primaries and glass
/// indices at 550 nm. Illuminants are white (fenestra renders in sRGB with a D65 white).
pub fn named(name: &str) -> Option<Rgb> {
    let v = |r, g, b| Some(Rgb::new(r, g, b));
    match name {
        "metal-Au-eta" => v(0.143, 0.374, 1.442),
        "metal-Au-k" => v(3.983, 2.385, 1.603),
        "metal-Ag-eta" => v(0.155, 0.117, 0.138),
        "metal-Ag-k" => v(4.828, 3.122, 2.147),
        "metal-Al-eta" => v(1.657, 0.880, 0.521),
        "metal-Al-k" => v(9.224, 6.270, 4.837),
        "metal-Cu-eta" => v(0.200, 0.924, 1.102),
        "metal-Cu-k" => v(3.912, 2.452, 2.142),
        "metal-CuZn-eta" => v(0.444, 0.527, 1.094),
        "metal-CuZn-k" => v(3.695, 2.765, 1.829),
        "glass-BK7" => Some(Rgb::splat(1.5168)),
        "glass-BAF10" => Some(Rgb::splat(1.6700)),
        "glass-FK51A" => Some(Rgb::splat(1.4866)),
        "glass-LASF9" => Some(Rgb::splat(1.8503)),
        "glass-F5" | "glass-SF5" => Some(Rgb::splat(1.6727)),
        "glass-F10" | "glass-SF10" => Some(Rgb::splat(1.7283)),
        "glass-F11" | "glass-SF11" => Some(Rgb::splat(1.7847)),
        "stdillum-D65" | "illum-acesD60" | "stdillum-D50" | "stdillum-E" => Some(Rgb::ONE),
        "stdillum-A" => Some(blackbody(2856.0)),
        _ => None,
    }
}

/// All names [`named`] knows, for error messages.
pub const NAMES: &str = "metal-{Au,Ag,Al,Cu,CuZn}-{eta,k}, glass-{BK7,BAF10,FK51A,LASF9,F5,F10,F11}, stdillum-{D65,D50,E,A}";

/// Why a spectrum has no colour, or a spectrum file no spectrum.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum SpectrumError {
    /// A blackbody of zero or negative temperature.
    #[error("blackbody temperature {0} must be positive")]
    Blackbody(f32),
    /// Sampled values with no samples.
    #[error("empty spectrum")]
    Empty,
    /// A name [`named`] does not know.
    #[error("unknown named spectrum \"{0}\" (known: {NAMES})")]
    UnknownName(String),
    /// A spectrum file that cannot be read.
    #[error("cannot read spectrum file {path}: {reason}")]
    Unreadable { path: String, reason: String },
    /// A word of a spectrum file that is not a number.
    #[error("{path}:{line}: \"{word}\" is not a number")]
    NotANumber {
        path: String,
        line: usize,
        word: String,
    },
    /// A spectrum file whose numbers do not pair up.
    #[error("{path}: {count} numbers, not (wavelength, value) pairs")]
    NotPairs { path: String, count: usize },
    /// A spectrum file whose wavelengths do not increase.
    #[error("{path}: wavelengths must increase")]
    NotIncreasing { path: String },
}

/// The RGB value of a spectrum parameter, or why it has none.
pub fn to_rgb(s: &SpectrumParam) -> Result<Rgb, SpectrumError> {
    match s {
        SpectrumParam::Rgb(c) => Ok(*c),
        SpectrumParam::Blackbody(t) if *t > 0.0 => Ok(blackbody(*t)),
        SpectrumParam::Blackbody(t) => Err(SpectrumError::Blackbody(*t)),
        SpectrumParam::Sampled(p) if p.is_empty() => Err(SpectrumError::Empty),
        SpectrumParam::Sampled(p) => Ok(sampled(p)),
        SpectrumParam::Named(n) => named(n).ok_or_else(|| SpectrumError::UnknownName(n.clone())),
    }
}

/// Whether a "spectrum" string names a file (rather than one of the named spectra).
pub fn names_file(name: &str) -> bool {
    named(name).is_none() && name.contains('.')
}

/// A spectrum file as pbrt-v4 reads it: (wavelength nm, value) pairs as whitespace-separated
/// numbers, `#` starting a comment.
pub fn read_file(path: &std::path::Path) -> Result<Vec<(f32, f32)>, SpectrumError> {
    let shown = || path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| SpectrumError::Unreadable {
        path: shown(),
        reason: e.to_string(),
    })?;
    let mut numbers = Vec::new();
    for (no, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("");
        for word in line.split_whitespace() {
            match word.parse::<f32>() {
                Ok(x) if x.is_finite() => numbers.push(x),
                _ => {
                    return Err(SpectrumError::NotANumber {
                        path: shown(),
                        line: no + 1,
                        word: word.to_string(),
                    })
                }
            }
        }
    }
    if numbers.is_empty() || numbers.len() % 2 != 0 {
        return Err(SpectrumError::NotPairs {
            path: shown(),
            count: numbers.len(),
        });
    }
    let pairs: Vec<(f32, f32)> = numbers.chunks_exact(2).map(|c| (c[0], c[1])).collect();
    if pairs.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err(SpectrumError::NotIncreasing { path: shown() });
    }
    Ok(pairs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_spectra_are_grey_and_blackbodies_have_the_right_hue() {
        let g = sampled(&[(360.0, 0.5), (830.0, 0.5)]);
        assert!((g.r - 0.5).abs() < 1e-4 && (g.g - 0.5).abs() < 1e-4 && (g.b - 0.5).abs() < 1e-4);
        // 0 beyond its ends, as pbrt-v4 has it: what the observer sees outside 400-700 nm is
        // lost, most of it in blue.
        let cut = sampled(&[(400.0, 0.5), (700.0, 0.5)]);
        assert!(cut.b < 0.4975 && cut.r < 0.499, "{cut:?}");
        assert!(
            (0..3).all(|c| (cut.to_array()[c] - 0.5).abs() < 0.01),
            "{cut:?}"
        );
        let warm = blackbody(2700.0);
        let cool = blackbody(10000.0);
        assert!(warm.r > warm.g && warm.g > warm.b, "{warm:?}");
        assert!(cool.b > cool.r, "{cool:?}");
        assert!((warm.luminance() - 1.0).abs() < 1e-4);
        // Near the equal-energy white point a blackbody is nearly neutral.
        let e = blackbody(5455.0);
        assert!((e.r / e.b - 1.0).abs() < 0.15, "{e:?}");
    }

    /// Lights' spectra as pbrt-v4 renders them: a distant light on a diffuse plane of
    /// reflectance 0.5 rendered by pbrt-v4 (its CPU build, 16x16 at 1024 spp, the image
    /// means): an equal-energy light (0.1911, 0.1512, 0.1437) whatever its magnitude, a 2700 K
    /// blackbody (0.3081, 0.1279, 0.0305), a 6500 K one at scale 2 (0.3321, 0.3131, 0.3290),
    /// rgb (1, 1, 1) (0.1592, 0.1592, 0.1589): one luminance for all. The hues agree within
    /// 0.6% (pbrt-v4's four digits; with an analytic fit of the CIE tables they were 2% off).
    #[test]
    fn light_spectra_have_pbrt_v4s_colours_and_unit_luminance() {
        let close = |c: Rgb, pbrt: [f32; 3]| {
            let (c, p) = (c / c.g, Rgb::new(pbrt[0], pbrt[1], pbrt[2]) / pbrt[1]);
            (c.r / p.r - 1.0).abs() < 0.006 && (c.b / p.b - 1.0).abs() < 0.006
        };
        for (s, pbrt) in [
            (
                SpectrumParam::Sampled(vec![(400.0, 1.0), (700.0, 1.0)]),
                [0.1911, 0.1512, 0.1437],
            ),
            (
                SpectrumParam::Sampled(vec![(400.0, 5.0), (700.0, 5.0)]),
                [0.1911, 0.1512, 0.1437],
            ),
            (SpectrumParam::Blackbody(2700.0), [0.3081, 0.1279, 0.0305]),
            (SpectrumParam::Blackbody(6500.0), [0.3321, 0.3131, 0.3290]),
        ] {
            let c = illuminant_to_rgb(&s).expect("rgb");
            assert!(close(c, pbrt), "{s:?}: {c:?}, pbrt-v4 {pbrt:?}");
            assert!((c.luminance() - 1.0).abs() < 1e-4, "{c:?}");
        }
        let rgb = Rgb::new(1.0, 2.0, 3.0);
        assert_eq!(illuminant_to_rgb(&SpectrumParam::Rgb(rgb)), Ok(rgb));
    }

    #[test]
    fn spectrum_files_are_pairs_with_comments() {
        let dir = std::env::temp_dir().join(format!("fenestra-spd-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let file = |name: &str, text: &str| {
            let path = dir.join(name);
            std::fs::write(&path, text).expect("write");
            path
        };
        let good = file(
            "flat.spd",
            "# measured\n360 0.5  500 0.5 # mid\n600 0.5\n830 0.5\n",
        );
        let pairs = read_file(&good).expect("pairs");
        assert_eq!(pairs.len(), 4);
        let grey = to_rgb(&SpectrumParam::Sampled(pairs)).expect("rgb");
        assert!(
            (grey.r - 0.5).abs() < 1e-4 && (grey.b - 0.5).abs() < 1e-4,
            "{grey:?}"
        );
        for (text, says) in [
            ("400 0.5 500", "3 numbers, not (wavelength, value) pairs"),
            ("400 0.5\n500 x", ":2: \"x\" is not a number"),
            ("500 0.5 400 0.5", "wavelengths must increase"),
        ] {
            let e = read_file(&file("bad.spd", text))
                .expect_err(says)
                .to_string();
            assert!(e.contains(says), "{e}");
        }
        assert!(read_file(&dir.join("missing.spd"))
            .expect_err("missing")
            .to_string()
            .contains("cannot read spectrum file"));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn red_spectrum_is_red() {
        let r = sampled(&[(400.0, 0.0), (580.0, 0.0), (600.0, 1.0), (700.0, 1.0)]);
        assert!(r.r > 0.5 && r.g < 0.3 && r.b < 0.1, "{r:?}");
        assert!(to_rgb(&SpectrumParam::Named("metal-Xx-eta".into())).is_err());
    }
}
