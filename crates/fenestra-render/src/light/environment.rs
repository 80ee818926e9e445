//! Environment lights: constant radiance, or a latitude-longitude image importance-sampled by
//! a piecewise-constant distribution over its pixels (luminance times sin(theta)).

use super::LightSample;
use fenestra_core::distribution::Distribution2D;
use fenestra_core::image::Image;
use fenestra_core::{warp, Rgb, Vec2, Vec3, PI};
use fenestra_scene::{EnvironmentDesc, Scene};
use glam::Mat3;
use std::sync::Arc;

/// Light from infinitely far away.
#[derive(Clone, Debug)]
pub enum Environment {
    /// The same radiance everywhere.
    Constant(Rgb),
    /// A latitude-longitude image.
    Image(ImageEnvironment),
}

#[derive(Clone, Debug)]
pub struct ImageEnvironment {
    image: Arc<Image>,
    scale: Rgb,
    to_world: Mat3,
    to_local: Mat3,
    distribution: Distribution2D,
}

impl Environment {
    /// The light of `desc`, with its sampling distribution.
    pub fn new(desc: &EnvironmentDesc) -> Self {
        match desc {
            EnvironmentDesc::Constant(l) => Environment::Constant(*l),
            EnvironmentDesc::Image {
                image,
                scale,
                to_world,
            } => {
                let (w, h) = (image.width, image.height);
                let mut func = vec![0.0f32; w * h];
                for y in 0..h {
                    let sin_theta = (PI * (y as f32 + 0.5) / h as f32).sin();
                    for x in 0..w {
                        func[y * w + x] =
                            (image.get(x, y) * *scale).luminance().max(0.0) * sin_theta;
                    }
                }
                // Rotation part only, so directions stay unit length.
                let to_world = Mat3::from_cols(
                    to_world.x_axis.normalize(),
                    to_world.y_axis.normalize(),
                    to_world.z_axis.normalize(),
                );
                Environment::Image(ImageEnvironment {
                    image: image.clone(),
                    scale: *scale,
                    to_world,
                    to_local: to_world.inverse(),
                    distribution: Distribution2D::new(&func, w, h),
                })
            }
        }
    }

    /// Radiance arriving along -`dir` from the environment (`dir` points away from the scene).
    pub fn le(&self, dir: Vec3) -> Rgb {
        match self {
            Environment::Constant(l) => *l,
            Environment::Image(e) => {
                let uv = e.uv(dir);
                let x = ((uv.x * e.image.width as f32) as usize).min(e.image.width - 1);
                let y = ((uv.y * e.image.height as f32) as usize).min(e.image.height - 1);
                e.image.get(x, y) * e.scale
            }
        }
    }

    /// A direction by the image's luminance (uniform for a constant sky).
    pub fn sample_li(&self, u: Vec2) -> Option<LightSample> {
        let (wi, pdf) = match self {
            Environment::Constant(_) => {
                (warp::square_to_uniform_sphere(u), warp::UNIFORM_SPHERE_PDF)
            }
            Environment::Image(e) => {
                let (uv, pdf_uv) = e.distribution.sample(u);
                let theta = uv.y * PI;
                let phi = uv.x * 2.0 * PI;
                let sin_t = theta.sin();
                if sin_t <= 0.0 || pdf_uv <= 0.0 {
                    return None;
                }
                let local = Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), theta.cos());
                (e.to_world * local, pdf_uv / (2.0 * PI * PI * sin_t))
            }
        };
        Some(LightSample {
            wi,
            li: self.le(wi),
            pdf,
            point: None,
            delta: false,
        })
    }

    /// Solid-angle density of `sample_li` giving `dir`.
    pub fn pdf_li(&self, dir: Vec3) -> f32 {
        match self {
            Environment::Constant(_) => warp::UNIFORM_SPHERE_PDF,
            Environment::Image(e) => {
                let uv = e.uv(dir);
                let sin_t = (uv.y * PI).sin();
                if sin_t <= 0.0 {
                    0.0
                } else {
                    e.distribution.pdf(uv) / (2.0 * PI * PI * sin_t)
                }
            }
        }
    }

    /// Power through the scene's bounding disk (pbrt-v4's convention).
    pub fn power(&self, scene: &Scene) -> f32 {
        let r = scene.bounding_sphere().1;
        let mean = match self {
            Environment::Constant(l) => l.luminance(),
            Environment::Image(e) => (e.image.mean() * e.scale).luminance(),
        };
        // pbrt-v4's convention: pi r^2 times the radiance integrated over the sphere.
        PI * r * r * 4.0 * PI * mean
    }
}

impl ImageEnvironment {
    fn uv(&self, dir: Vec3) -> Vec2 {
        let d = (self.to_local * dir).normalize();
        let theta = d.z.clamp(-1.0, 1.0).acos();
        let phi = d.y.atan2(d.x).rem_euclid(2.0 * PI);
        Vec2::new(phi / (2.0 * PI), theta / PI)
    }
}
