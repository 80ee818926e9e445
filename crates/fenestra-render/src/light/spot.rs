//! Spot light with pbrt-v4's smoothstep falloff between two cone angles.

use super::LightSample;
use fenestra_core::{warp, Frame, Rgb, Vec2, Vec3, PI};

/// A spot light with pbrt-v4's smoothstep falloff.
#[derive(Clone, Debug)]
pub struct SpotLight {
    position: Vec3,
    direction: Vec3,
    intensity: Rgb,
    cos_end: f32,
    cos_start: f32,
}

fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    if a == b {
        return if x < a { 0.0 } else { 1.0 };
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl SpotLight {
    /// `cone_angle` is the total half-angle, `falloff_start` where the falloff begins (degrees).
    pub fn new(
        position: Vec3,
        direction: Vec3,
        intensity: Rgb,
        cone_angle: f32,
        falloff_start: f32,
    ) -> Self {
        SpotLight {
            position,
            direction: direction.normalize(),
            intensity,
            cos_end: cone_angle.to_radians().cos(),
            cos_start: falloff_start.to_radians().cos(),
        }
    }

    /// Position, unit axis, cosines of the falloff's start and of the cone's edge, and the
    /// intensity on the axis.
    pub fn cone(&self) -> (Vec3, Vec3, f32, f32, Rgb) {
        (
            self.position,
            self.direction,
            self.cos_start,
            self.cos_end,
            self.intensity,
        )
    }

    /// A ray leaving the spot in a direction uniform within its outer cone.
    pub fn sample_ray(&self, u: Vec2) -> super::EmittedRay {
        let local = warp::square_to_uniform_cone(u, 1.0 - self.cos_end);
        let falloff = smoothstep(self.cos_end, self.cos_start, local.z);
        super::EmittedRay {
            origin: self.position,
            dir: Frame::from_normal(self.direction).to_world(local),
            // Uniform in the cone: density 1 / (2 pi (1 - cos_end)).
            power: self.intensity * (falloff * 2.0 * PI * (1.0 - self.cos_end)),
        }
    }

    /// The direction from `p` to the light and the radiance-like I(w)/d^2.
    pub fn sample_li(&self, p: Vec3) -> Option<LightSample> {
        let (wi, d2) = super::toward(self.position, p)?;
        let falloff = smoothstep(self.cos_end, self.cos_start, (-wi).dot(self.direction));
        if falloff == 0.0 {
            return None;
        }
        Some(LightSample {
            wi,
            li: self.intensity * (falloff / d2),
            pdf: 1.0,
            point: Some(self.position),
            delta: true,
        })
    }

    /// Emitted power (luminance of watts), falloff included.
    pub fn power(&self) -> f32 {
        // Full intensity inside the inner cone, smoothstep average (1/2) in the falloff ring.
        self.intensity.luminance()
            * 2.0
            * PI
            * ((1.0 - self.cos_start) + 0.5 * (self.cos_start - self.cos_end))
    }
}
