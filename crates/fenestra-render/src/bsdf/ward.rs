//! Anisotropic Ward BRDF with Walter's (2005) normalisation and half-vector sampling, as used
//! by seed 003 (§2.5, Table 2.1): rho_d/pi + rho_s exp(-tan^2(theta_h)(cos^2 phi_h/ax^2 +
//! sin^2 phi_h/ay^2)) / (4 pi ax ay sqrt(cos_i cos_o)).

use super::{reflect, specular_probability, BsdfSample};
use fenestra_core::{warp, Rgb, Vec2, Vec3, INV_PI, PI};
use fenestra_scene::material;

/// Anisotropic Ward with Walter's (2005) normalisation (seed 003 §2.5).
#[derive(Clone, Debug)]
pub struct Ward {
    diffuse: Rgb,
    specular: Rgb,
    ax: f32,
    ay: f32,
    p_specular: f32,
}

impl Ward {
    /// Ward with diffuse and specular albedos and roughness (ax, ay).
    pub fn new(diffuse: Rgb, specular: Rgb, ax: f32, ay: f32) -> Self {
        Ward {
            diffuse,
            specular,
            ax,
            ay,
            p_specular: specular_probability(diffuse, specular),
        }
    }

    /// exp(-(hx^2/ax^2 + hy^2/ay^2) / hz^2) for a unit half vector.
    fn exponential(&self, h: Vec3) -> f32 {
        let e = ((h.x / self.ax).powi(2) + (h.y / self.ay).powi(2)) / (h.z * h.z);
        (-e).exp()
    }

    /// Its Lambertian albedo and its glossy lobe alone (f = albedo / pi + the lobe's f).
    pub fn split(&self) -> (Rgb, Ward) {
        (
            self.diffuse,
            Ward::new(Rgb::ZERO, self.specular, self.ax, self.ay),
        )
    }

    /// f(wo, wi) in the local frame.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let h = (wo + wi).normalize_or_zero();
        if h.z <= 0.0 {
            return self.diffuse * INV_PI;
        }
        let spec = self.exponential(h) / (4.0 * PI * self.ax * self.ay * (wi.z * wo.z).sqrt());
        self.diffuse * INV_PI + self.specular * spec
    }

    /// Density of the half vector: the anisotropic Beckmann NDF times cos(theta_h).
    fn pdf_h(&self, h: Vec3) -> f32 {
        if h.z <= 0.0 {
            return 0.0;
        }
        self.exponential(h) / (PI * self.ax * self.ay * h.z * h.z * h.z)
    }

    /// Solid-angle density with which `sample` gives `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let h = (wo + wi).normalize_or_zero();
        let spec = if h == Vec3::ZERO {
            0.0
        } else {
            self.pdf_h(h) / (4.0 * wo.dot(h).abs())
        };
        self.p_specular * spec + (1.0 - self.p_specular) * warp::cosine_hemisphere_pdf(wi)
    }

    /// Samples an incident direction for `wo`.
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let wi = if uc < self.p_specular {
            // Walter 2005, eqs. 6-7.
            let a = 2.0 * PI * u.y;
            let phi = (self.ay * a.sin()).atan2(self.ax * a.cos());
            let (s, c) = phi.sin_cos();
            let tan2 =
                -(1.0 - u.x).ln() / (c * c / (self.ax * self.ax) + s * s / (self.ay * self.ay));
            let cos_t = 1.0 / (1.0 + tan2).sqrt();
            let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
            reflect(wo, Vec3::new(sin_t * c, sin_t * s, cos_t))
        } else {
            warp::square_to_cosine_hemisphere(u)
        };
        BsdfSample::reflected(wi, |wi| self.eval(wo, wi), |wi| self.pdf(wo, wi))
    }
}

impl From<&material::Ward> for Ward {
    fn from(m: &material::Ward) -> Self {
        Ward::new(m.diffuse, m.specular, m.alpha_x, m.alpha_y)
    }
}
