//! The sun's disk as seen through a clear atmosphere: the direct-beam part of Bird and
//! Riordan's SPECTRL2 clear-sky spectral model (J. Climate Appl. Meteor. 25(1), 1986): the
//! extraterrestrial spectrum attenuated by Rayleigh scattering, aerosols (Angstrom's law,
//! alpha = 1.3), ozone, water vapour and mixed gases along the relative air mass, integrated
//! against the CIE observer.
//!
//! The aerosol's Angstrom coefficient beta comes from the sky's turbidity through a table
//! fit so that the sun agrees with the Hosek-Wilkie solar radiance the sky model was built
//! with (Hosek and Wilkie 2013, as Mitsuba 3.9.1's `sunsky` gives it): least squares in log
//! illuminance over elevations 20-80 degrees, which leaves the sun within 8% of theirs there
//! and 0.75-0.78 of theirs at 10 degrees (their sun fades less towards the horizon than any
//! Beer-Lambert beam does). Preetham et al.'s relation (beta = 0.04608 T - 0.04586) was
//! tried first: it made the turbidity-6 sun 0.14-0.77 of the sky model's (docs/scenes.md).

use fenestra_core::spectrum::spectrum_to_linear_srgb;
use fenestra_core::Rgb;

/// The sun's mean angular radius (0.533 degrees across).
pub const SUN_HALF_ANGLE_DEG: f32 = 0.2666;

/// Ozone column (atm-cm) and precipitable water (cm) of the U.S. standard atmosphere, the
/// values Bird and Riordan use.
const OZONE_CM: f64 = 0.35;
const WATER_CM: f64 = 1.42;

/// Ozone's mean height (km) and the Earth's radius (km), for ozone's own air mass.
const OZONE_HEIGHT_KM: f64 = 22.0;
const EARTH_RADIUS_KM: f64 = 6370.0;

/// SPECTRL2's table over the visible band (Bird and Riordan 1986, Table 1): wavelength (nm),
/// extraterrestrial irradiance (W/(m^2 nm)) at the mean Earth-Sun distance, and the ozone,
/// water vapour and mixed-gas absorption coefficients.
#[rustfmt::skip]
const TABLE: [(f64, f64, f64, f64, f64); 42] = [
    (350.0, 0.9755, 0.007, 0.0, 0.0), (360.0, 0.9759, 0.0, 0.0, 0.0),
    (370.0, 1.1199, 0.0, 0.0, 0.0), (380.0, 1.1038, 0.0, 0.0, 0.0),
    (390.0, 1.0338, 0.0, 0.0, 0.0), (400.0, 1.4791, 0.0, 0.0, 0.0),
    (410.0, 1.7013, 0.0, 0.0, 0.0), (420.0, 1.7404, 0.0, 0.0, 0.0),
    (430.0, 1.5872, 0.0, 0.0, 0.0), (440.0, 1.837, 0.0, 0.0, 0.0),
    (450.0, 2.005, 0.003, 0.0, 0.0), (460.0, 2.043, 0.006, 0.0, 0.0),
    (470.0, 1.987, 0.009, 0.0, 0.0), (480.0, 2.027, 0.014, 0.0, 0.0),
    (490.0, 1.896, 0.021, 0.0, 0.0), (500.0, 1.909, 0.03, 0.0, 0.0),
    (510.0, 1.927, 0.04, 0.0, 0.0), (520.0, 1.831, 0.048, 0.0, 0.0),
    (530.0, 1.891, 0.063, 0.0, 0.0), (540.0, 1.898, 0.075, 0.0, 0.0),
    (550.0, 1.892, 0.085, 0.0, 0.0), (570.0, 1.84, 0.12, 0.0, 0.0),
    (593.0, 1.768, 0.119, 0.075, 0.0), (610.0, 1.728, 0.12, 0.0, 0.0),
    (630.0, 1.658, 0.09, 0.0, 0.0), (656.0, 1.524, 0.065, 0.0, 0.0),
    (667.6, 1.531, 0.051, 0.0, 0.0), (690.0, 1.42, 0.028, 0.016, 0.15),
    (710.0, 1.399, 0.018, 0.0125, 0.0), (718.0, 1.374, 0.015, 1.8, 0.0),
    (724.4, 1.373, 0.012, 2.5, 0.0), (740.0, 1.298, 0.01, 0.061, 0.0),
    (752.5, 1.269, 0.008, 0.0008, 0.0), (757.5, 1.245, 0.007, 0.0001, 0.0),
    (762.5, 1.223, 0.006, 1e-05, 4.0), (767.5, 1.205, 0.005, 1e-05, 0.35),
    (780.0, 1.183, 0.0, 0.0006, 0.0), (800.0, 1.148, 0.0, 0.036, 0.0),
    (816.0, 1.091, 0.0, 1.6, 0.0), (823.7, 1.062, 0.0, 2.5, 0.0),
    (831.5, 1.038, 0.0, 0.5, 0.0), (840.0, 1.022, 0.0, 0.155, 0.0),
];

/// Angstrom's beta for turbidity 1, 2, ..., 10 (see the module's header).
const BETA: [f64; 10] = [
    0.0375, 0.0425, 0.05, 0.0625, 0.0775, 0.0875, 0.1025, 0.13, 0.175, 0.25,
];

/// Angstrom's beta at `turbidity` (1 to 10), linear between the table's entries.
fn angstrom_beta(turbidity: f64) -> f64 {
    let t = turbidity.clamp(1.0, 10.0) - 1.0;
    let i = (t.floor() as usize).min(BETA.len() - 2);
    let f = t - i as f64;
    BETA[i] * (1.0 - f) + BETA[i + 1] * f
}

/// Relative optical air mass at `elevation_deg` above the horizon (Kasten and Young 1989).
pub fn air_mass(elevation_deg: f64) -> f64 {
    let zenith = 90.0 - elevation_deg;
    1.0 / (zenith.to_radians().cos() + 0.50572 * (96.07995 - zenith).powf(-1.6364))
}

/// Direct normal spectral irradiance (W/(m^2 nm)) at the table's wavelengths for the sun
/// at `elevation_deg` through an atmosphere of `turbidity` (SPECTRL2's eqs. 2-9, at sea
/// level).
fn direct_normal(elevation_deg: f64, turbidity: f64) -> [(f64, f64); 42] {
    let m = air_mass(elevation_deg);
    let cos_z = (90.0 - elevation_deg).to_radians().cos();
    let h = OZONE_HEIGHT_KM / EARTH_RADIUS_KM;
    let m_ozone = (1.0 + h) / (cos_z * cos_z + 2.0 * h).sqrt();
    let beta = angstrom_beta(turbidity);
    TABLE.map(|(nm, et, ozone, water, mixed)| {
        let l = nm * 1e-3;
        let rayleigh = (-m / (l.powi(4) * (115.6406 - 1.335 / (l * l)))).exp();
        let aerosol = (-beta * l.powf(-1.3) * m).exp();
        let aw = water * WATER_CM * m;
        let water = (-0.2385 * aw / (1.0 + 20.07 * aw).powf(0.45)).exp();
        let ozone = (-ozone * OZONE_CM * m_ozone).exp();
        let au = mixed * m;
        let mixed = (-1.41 * au / (1.0 + 118.93 * au).powf(0.45)).exp();
        (nm, et * rayleigh * aerosol * water * ozone * mixed)
    })
}

/// The sun's direct normal irradiance as linear sRGB (luminance = illuminance / 683 lm/W)
/// at `elevation_deg` above the horizon, through an atmosphere of `turbidity`.
pub fn irradiance(elevation_deg: f32, turbidity: f32) -> Rgb {
    to_rgb(&direct_normal(elevation_deg as f64, turbidity as f64))
}

/// Linear sRGB of the piecewise-linear spectrum through `points` (nm, value), in the gamut.
fn to_rgb(points: &[(f64, f64)]) -> Rgb {
    let rgb = spectrum_rgb(points);
    // A sun within a few degrees of the horizon is redder than sRGB's gamut holds (a negative
    // blue): clip to the gamut and keep the luminance, which is the illuminance / 683 lm/W.
    let clipped = Rgb::new(rgb.r.max(0.0), rgb.g.max(0.0), rgb.b.max(0.0));
    if clipped == rgb || clipped.luminance() <= 0.0 {
        clipped
    } else {
        clipped * (rgb.luminance().max(0.0) / clipped.luminance())
    }
}

/// Linear sRGB of the piecewise-linear spectrum through `points`, out of gamut as it falls.
fn spectrum_rgb(points: &[(f64, f64)]) -> Rgb {
    let at = |l: f64| {
        let i = points
            .partition_point(|p| p.0 < l)
            .clamp(1, points.len() - 1);
        let (a, b) = (points[i - 1], points[i]);
        let t = ((l - a.0) / (b.0 - a.0)).clamp(0.0, 1.0);
        a.1 + t * (b.1 - a.1)
    };
    let [r, g, b] = spectrum_to_linear_srgb(at);
    Rgb::new(r as f32, g as f32, b as f32)
}

/// The radiance of the sun's disk: its irradiance spread uniformly over the disk's solid
/// angle (no limb darkening).
pub fn radiance(elevation_deg: f32, turbidity: f32) -> Rgb {
    irradiance(elevation_deg, turbidity) / disk_solid_angle()
}

/// Solid angle of the sun's disk (sr).
pub fn disk_solid_angle() -> f32 {
    let c = (SUN_HALF_ANGLE_DEG as f64).to_radians().cos();
    (2.0 * std::f64::consts::PI * (1.0 - c)) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn air_mass_is_one_overhead_and_finite_at_the_horizon() {
        assert!((air_mass(90.0) - 1.0).abs() < 1e-3);
        assert!((air_mass(30.0) - 1.9943).abs() < 2e-3, "{}", air_mass(30.0));
        // Kasten and Young's table gives 38.09 at the horizon, their fit 37.92.
        assert!((air_mass(0.0) - 38.09).abs() < 0.2, "{}", air_mass(0.0));
    }

    #[test]
    fn the_sun_outside_the_atmosphere_gives_the_solar_illuminance() {
        // With no atmosphere (every coefficient off) the table integrates to the solar
        // illuminance constant, about 133 klux (the value of the extraterrestrial spectrum
        // Bird and Riordan tabulate; the CIE gives 133.3 klux).
        let outside = TABLE.map(|(nm, et, ..)| (nm, et));
        let y = to_rgb(&outside).luminance() as f64;
        let lux = y * 683.0;
        assert!((lux / 133_300.0 - 1.0).abs() < 0.02, "{lux} lux");
    }

    #[test]
    fn a_sun_at_every_elevation_has_a_usable_radiance() {
        // Near the horizon the sun's spectrum is so red that its blue falls outside the sRGB
        // gamut: a negative channel, which the scene check refused below 3 degrees.
        for tenth in 0..=900 {
            let e = tenth as f32 / 10.0;
            for turbidity in [1.0, 3.0, 10.0] {
                let l = radiance(e, turbidity);
                assert!(
                    l.is_finite() && l.r >= 0.0 && l.g >= 0.0 && l.b >= 0.0,
                    "elevation {e}, turbidity {turbidity}: {l:?}"
                );
            }
        }
        // Clipped to the gamut with the illuminance kept.
        let unclipped = spectrum_rgb(&direct_normal(1.0, 3.0));
        assert!(unclipped.b < 0.0, "the case is out of gamut: {unclipped:?}");
        let kept = irradiance(1.0, 3.0).luminance() / unclipped.luminance();
        assert!((kept - 1.0).abs() < 1e-4, "{kept}");
    }
}
