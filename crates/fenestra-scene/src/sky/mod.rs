//! A physical clear sky and sun for any scene. The sky is Hosek and Wilkie's model ("An
//! Analytic Model for Full Spectral Sky-Dome Radiance", SIGGRAPH 2012; its RGB fit, evaluated
//! by the `hw-skymodel` crate) baked into a latitude-longitude map; below the horizon a
//! Lambertian ground of the sky's albedo, lit by that sky and the sun. The sun is a disk of
//! its true angular size and the radiance module `sun` gives it.
//!
//! Why Hosek-Wilkie rather than Preetham 1999: it is fit to brute-force simulations of a
//! scattering atmosphere over the whole turbidity range, models the ground albedo, and keeps
//! the horizon and circumsolar region that Preetham's model gets wrong at low sun and high
//! turbidity (Hosek and Wilkie, section 7; Kider et al. 2014 measured both against
//! photographs); it costs the same to evaluate. Mitsuba 3's `sunsky` uses the same model,
//! which makes it a judge (docs/scenes.md).
//!
//! Units: the RGB fit integrates spectral radiance against the unnormalised CIE observer,
//! so a pixel's luminance is the sky's luminance over 683 lm/W, the unit of fenestra's
//! lights (a glTF light of 683 lm is one watt).

pub mod solar_position;
pub mod sun;

use crate::environment::{latlong_direction, EnvironmentMap};
use crate::light::{EnvironmentDesc, LightDesc};
use crate::scene::SceneDesc;
use fenestra_core::image::Image;
use fenestra_core::{Rgb, Vec3, PI};
use hw_skymodel::rgb::{Channel, SkyParams, SkyState};
use std::sync::Arc;

/// Width of the baked sky map (0.35 degrees a pixel).
pub const SKY_MAP_WIDTH: usize = 1024;

/// A clear sky with its sun.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sky {
    /// Atmospheric turbidity, 1 (arctic clear) to 10 (hazy); 3 is a clear temperate day.
    pub turbidity: f32,
    /// The ground's albedo (the model's, and the ground below the horizon).
    pub albedo: f32,
    /// The sun's elevation above the horizon (degrees, 0 to 90).
    pub elevation_deg: f32,
    /// The sun's azimuth clockwise from north seen from above (degrees); north is the map's
    /// phi = 0 direction (the environment frame's x axis, turned by its rotation).
    pub azimuth_deg: f32,
}

impl Sky {
    /// Why the model cannot give this sky, if it cannot.
    pub fn validate(&self) -> Option<String> {
        if !(1.0..=10.0).contains(&self.turbidity) {
            return Some(format!(
                "turbidity must lie in [1, 10] (the range Hosek and Wilkie fit), got {}",
                self.turbidity
            ));
        }
        if !(0.0..=1.0).contains(&self.albedo) {
            return Some(format!(
                "ground albedo must lie in [0, 1], got {}",
                self.albedo
            ));
        }
        if !(0.0..=90.0).contains(&self.elevation_deg) {
            return Some(format!(
                "the sun's elevation must lie in [0, 90] degrees (the model covers a sun above the horizon), got {}",
                self.elevation_deg
            ));
        }
        if !self.azimuth_deg.is_finite() {
            return Some(format!(
                "the sun's azimuth must be finite, got {}",
                self.azimuth_deg
            ));
        }
        None
    }

    /// Unit vector towards the sun in the map's frame (z up, azimuth clockwise from x).
    pub fn sun_direction(&self) -> Vec3 {
        let (el, az) = (
            self.elevation_deg.to_radians(),
            -self.azimuth_deg.to_radians(),
        );
        Vec3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin())
    }

    /// Radiance of the sun's disk.
    pub fn sun_radiance(&self) -> Rgb {
        sun::radiance(self.elevation_deg, self.turbidity)
    }

    /// The sky's radiance (Hosek-Wilkie) along directions of its frame (z up), above the
    /// horizon. Panics for a sky [`Sky::validate`] refuses.
    pub fn radiance(&self) -> impl Fn(Vec3) -> Rgb {
        let state = SkyState::new(&SkyParams {
            elevation: self.elevation_deg.to_radians(),
            turbidity: self.turbidity,
            albedo: [self.albedo; 3],
        })
        .expect("a validated sky is in the model's range");
        let sun = self.sun_direction();
        move |d: Vec3| {
            let theta = d.z.clamp(0.0, 1.0).acos();
            let gamma = d.dot(sun).clamp(-1.0, 1.0).acos();
            let l = [Channel::R, Channel::G, Channel::B]
                .map(|c| state.radiance(theta, gamma, c).max(0.0));
            Rgb::new(l[0], l[1], l[2])
        }
    }

    /// The sky as a `SKY_MAP_WIDTH` x `SKY_MAP_WIDTH / 2` latitude-longitude map in its
    /// frame (row 0 at the zenith), without the sun's disk; below the horizon the ground.
    /// Panics for a sky [`Sky::validate`] refuses.
    pub fn map(&self) -> Image {
        let (w, h) = (SKY_MAP_WIDTH, SKY_MAP_WIDTH / 2);
        let radiance = self.radiance();
        let mut image = Image::new(w, h);
        for y in 0..h / 2 {
            for x in 0..w {
                image.set(x, y, radiance(latlong_direction(x, y, w, h)));
            }
        }
        let ground = (sky_irradiance(&image) + self.sun_irradiance()) * (self.albedo / PI);
        for y in h / 2..h {
            for x in 0..w {
                image.set(x, y, ground);
            }
        }
        image
    }

    /// The sun's irradiance on a horizontal surface.
    pub fn sun_irradiance(&self) -> Rgb {
        sun::irradiance(self.elevation_deg, self.turbidity) * self.elevation_deg.to_radians().sin()
    }
}

/// Irradiance on a horizontal surface from the upper half of a latitude-longitude `map`
/// (each pixel's radiance times the integral of the cosine over it).
pub fn sky_irradiance(map: &Image) -> Rgb {
    let (w, h) = (map.width, map.height);
    let mut e = Rgb::ZERO;
    for y in 0..h / 2 {
        let (t0, t1) = (PI * y as f32 / h as f32, PI * (y + 1) as f32 / h as f32);
        let solid_angle = (t0.cos() - t1.cos()) * 2.0 * PI / w as f32;
        let cos = (PI * (y as f32 + 0.5) / h as f32).cos();
        for x in 0..w {
            e += map.get(x, y) * (cos * solid_angle);
        }
    }
    e
}

impl SceneDesc {
    /// The scene lit by `sky` and its sun instead of the environments it had (its other
    /// lights stay): the sky's pole along `up`, turned by `rotation_deg` about it as an
    /// environment map is, its radiance and the sun's times `strength`.
    /// Refuses a sky that does not validate, and a placement `EnvironmentMap::validate`
    /// refuses.
    pub fn with_sky(
        self,
        sky: &Sky,
        up: Vec3,
        rotation_deg: f32,
        strength: f32,
    ) -> Result<SceneDesc, SkyError> {
        if let Some(problem) = sky.validate() {
            return Err(SkyError::Sky(problem));
        }
        let map = EnvironmentMap {
            image: Arc::new(sky.map()),
            up,
            rotation_deg,
            strength,
        };
        if let Some(problem) = map.validate() {
            return Err(SkyError::Placement(problem));
        }
        let mut desc = self.with_environment(&map);
        desc.lights
            .push(LightDesc::Environment(EnvironmentDesc::Sun {
                direction: (map.to_world() * sky.sun_direction()).normalize(),
                radiance: sky.sun_radiance() * strength,
                half_angle: sun::SUN_HALF_ANGLE_DEG.to_radians(),
            }));
        Ok(desc)
    }
}

/// Why a sky cannot light a scene.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SkyError {
    /// The sky's own values (turbidity, albedo, the sun's elevation) are outside the model.
    #[error("{0}")]
    Sky(String),
    /// Its placement (up axis, turn, strength) is refused.
    #[error("{0}")]
    Placement(String),
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sky(turbidity: f32, elevation_deg: f32) -> Sky {
        Sky {
            turbidity,
            albedo: 0.3,
            elevation_deg,
            azimuth_deg: 0.0,
        }
    }

    fn close(a: Rgb, b: [f32; 3], tol: f32) -> bool {
        [(a.r, b[0]), (a.g, b[1]), (a.b, b[2])]
            .iter()
            .all(|(x, y)| (x / y - 1.0).abs() < tol)
    }

    #[test]
    fn the_sky_gives_the_models_radiance_at_zenith_and_horizon() {
        // Mitsuba 3.9.1's `sunsky` (the same Hosek-Wilkie RGB fit; its RGB is ours over the
        // CIE y-bar integral, 106.857), albedo 0.3, the sun at azimuth 0: the zenith, and
        // 1 degree above the horizon a quarter turn from the sun.
        let h = 89f32.to_radians();
        let horizon = Vec3::new(0.0, h.sin(), h.cos());
        for (t, el, zenith, side) in [
            (3.0, 45.0, [2.538, 4.436, 8.986], [14.31, 18.296, 20.09]),
            (3.0, 10.0, [0.894, 1.819, 3.193], [8.21, 8.227, 5.585]),
            (6.0, 45.0, [4.752, 6.629, 10.573], [15.304, 16.027, 17.252]),
        ] {
            let l = sky(t, el).radiance();
            assert!(
                close(l(Vec3::Z), zenith, 0.005),
                "T {t}, {el} deg: zenith {:?}",
                l(Vec3::Z)
            );
            assert!(
                close(l(horizon), side, 0.005),
                "T {t}, {el} deg: horizon {:?}",
                l(horizon)
            );
        }
    }

    #[test]
    fn the_suns_illuminance_is_spectrl2s_and_near_the_sky_models() {
        // Direct normal illuminance (lux) of SPECTRL2 (pvlib 0.16.1's `spectrl2` with our
        // aerosol beta, its Earth-Sun distance factor divided out, the CIE 1931 tables of
        // colour-science, which are our observer's), and of the
        // Hosek-Wilkie sun (Mitsuba 3.9.1's `sunsky`, its disk integrated).
        for (t, el, spectrl2, hosek_wilkie) in [
            (3.0, 45.0, 95_597.0, 91_449.0),
            (3.0, 10.0, 36_581.0, 48_472.0),
            (2.0, 70.0, 105_572.0, 98_451.0),
            (6.0, 30.0, 71_089.0, 71_106.0),
            (2.5, 60.0, 102_543.0, 95_734.0),
        ] {
            let ours = sun::irradiance(el, t).luminance() * 683.0;
            assert!(
                (ours / spectrl2 - 1.0).abs() < 0.01,
                "T {t}, {el} deg: {ours} lux, SPECTRL2 {spectrl2}"
            );
            let near = if el >= 20.0 { 0.08 } else { 0.25 };
            assert!(
                (ours / hosek_wilkie - 1.0).abs() < near,
                "T {t}, {el} deg: {ours} lux, Hosek-Wilkie {hosek_wilkie}"
            );
        }
    }

    #[test]
    fn the_ground_reflects_what_the_sky_and_sun_send_it() {
        // Below the horizon, albedo / pi times the horizontal irradiance of the map's upper
        // half (summed here in another order) and of the sun.
        let s = sky(3.0, 30.0);
        let map = s.map();
        let (w, h) = (map.width, map.height);
        let mut e = 0.0f64;
        for y in 0..h / 2 {
            let (t0, t1) = (PI * y as f32 / h as f32, PI * (y + 1) as f32 / h as f32);
            // The integral of cos over the row's band, per pixel.
            let band = 0.5 * (t1.sin().powi(2) - t0.sin().powi(2)) * 2.0 * PI / w as f32;
            let row: f64 = (0..w).map(|x| map.get(x, y).luminance() as f64).sum();
            e += row * band as f64;
        }
        e += (sun::irradiance(30.0, 3.0).luminance() * 0.5) as f64;
        let ground = map.get(3, h - 2).luminance() as f64;
        let expect = 0.3 * e / std::f64::consts::PI;
        assert!((ground / expect - 1.0).abs() < 2e-3, "{ground} vs {expect}");
        // And the sun's disk dominates it as a clear day's does (sun / sky about 4-9).
        let sky_part = e - (sun::irradiance(30.0, 3.0).luminance() * 0.5) as f64;
        let ratio = (sun::irradiance(30.0, 3.0).luminance() * 0.5) as f64 / sky_part;
        assert!((2.0..12.0).contains(&ratio), "sun / sky {ratio}");
    }

    #[test]
    fn the_sun_stands_where_its_angles_say() {
        let s = Sky {
            azimuth_deg: 90.0,
            ..sky(3.0, 30.0)
        };
        // East: a quarter turn clockwise from north (x), seen from above (z).
        let d = s.sun_direction();
        let c = 30f32.to_radians().cos();
        assert!((d - Vec3::new(0.0, -c, 0.5)).length() < 1e-6, "{d}");
        assert!(Sky {
            turbidity: 11.0,
            ..s
        }
        .validate()
        .is_some_and(|e| e.contains("turbidity")));
        assert!(Sky {
            elevation_deg: -1.0,
            ..s
        }
        .validate()
        .is_some_and(|e| e.contains("elevation")));
        assert!(Sky { albedo: 1.5, ..s }
            .validate()
            .is_some_and(|e| e.contains("albedo")));
    }
}
