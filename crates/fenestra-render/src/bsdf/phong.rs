//! Energy-normalised (modified) Phong: f = kd/pi + ks (n+2)/(2 pi) cos^n(alpha), alpha the
//! angle between wi and the mirror direction of wo (Lafortune and Willems 1994).

use super::{reflect_z, specular_probability, BsdfSample};
use fenestra_core::{warp, Frame, Rgb, Vec2, Vec3, INV_2PI, INV_PI};
use fenestra_scene::material;

/// Energy-normalised Phong: kd/pi + ks (n+2)/(2 pi) cos^n(alpha), lobes sampled in proportion to their albedos.
#[derive(Clone, Debug)]
pub struct Phong {
    diffuse: Rgb,
    specular: Rgb,
    exponent: f32,
    p_specular: f32,
}

impl Phong {
    /// Phong with albedos kd, ks and exponent n.
    pub fn new(diffuse: Rgb, specular: Rgb, exponent: f32) -> Self {
        Phong {
            diffuse,
            specular,
            exponent,
            p_specular: specular_probability(diffuse, specular),
        }
    }

    fn cos_alpha(wo: Vec3, wi: Vec3) -> f32 {
        reflect_z(wo).dot(wi).max(0.0)
    }

    /// Its Lambertian albedo and its glossy lobe alone (f = albedo / pi + the lobe's f).
    pub fn split(&self) -> (Rgb, Phong) {
        (
            self.diffuse,
            Phong::new(Rgb::ZERO, self.specular, self.exponent),
        )
    }

    /// f(wo, wi) in the local frame.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let n = self.exponent;
        self.diffuse * INV_PI
            + self.specular * ((n + 2.0) * INV_2PI * Self::cos_alpha(wo, wi).powf(n))
    }

    /// Solid-angle density with which `sample` gives `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let n = self.exponent;
        let spec = (n + 1.0) * INV_2PI * Self::cos_alpha(wo, wi).powf(n);
        self.p_specular * spec + (1.0 - self.p_specular) * warp::cosine_hemisphere_pdf(wi)
    }

    /// Samples an incident direction for `wo`.
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let wi = if uc < self.p_specular {
            // cos(alpha) = u^(1/(n+1)) around the mirror direction.
            let cos_a = u.x.powf(1.0 / (self.exponent + 1.0));
            let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
            let phi = 2.0 * fenestra_core::PI * u.y;
            Frame::from_normal(reflect_z(wo)).to_world(Vec3::new(
                sin_a * phi.cos(),
                sin_a * phi.sin(),
                cos_a,
            ))
        } else {
            warp::square_to_cosine_hemisphere(u)
        };
        BsdfSample::reflected(wi, |wi| self.eval(wo, wi), |wi| self.pdf(wo, wi))
    }
}

impl From<&material::Phong> for Phong {
    fn from(m: &material::Phong) -> Self {
        Phong::new(m.diffuse, m.specular, m.exponent)
    }
}
