//! Environment lights: constant radiance, a latitude-longitude image importance-sampled by
//! a piecewise-constant distribution over its pixels (luminance times sin(theta)), or the
//! sun's disk sampled uniformly in its cone.

use super::LightSample;
use fenestra_core::distribution::Distribution2D;
use fenestra_core::image::Image;
use fenestra_core::{warp, Frame, Rgb, Vec2, Vec3, PI};
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
    /// The sun's disk.
    Sun(SunDisk),
}

/// A disk of uniform radiance at infinity.
#[derive(Clone, Copy, Debug)]
pub struct SunDisk {
    /// Unit vector towards the centre, and a frame around it.
    frame: Frame,
    radiance: Rgb,
    /// 1 - cos of the angular radius: the cone's cap height.
    cap: f32,
}

impl SunDisk {
    /// Whether the unit direction `dir` meets the disk: 1 - cos(angle) = |dir - axis|^2 / 2,
    /// exact where the cosine of a half-degree angle would round.
    fn holds(&self, dir: Vec3) -> bool {
        0.5 * (dir - self.frame.n).length_squared() <= self.cap
    }

    /// Unit vector towards the disk's centre.
    pub fn axis(&self) -> Vec3 {
        self.frame.n
    }

    /// Its radiance.
    pub fn radiance(&self) -> Rgb {
        self.radiance
    }

    /// A direction towards the disk, uniform in its cone (every direction of the cone meets
    /// the disk: an edge test could round it off).
    pub fn sample(&self, u: Vec2) -> Vec3 {
        self.frame
            .to_world(warp::square_to_uniform_cone(u, self.cap))
    }

    /// Solid-angle density with which [`SunDisk::sample`] gives the direction `dir`.
    pub fn pdf(&self, dir: Vec3) -> f32 {
        if self.holds(dir.normalize()) {
            warp::uniform_cone_pdf(self.cap)
        } else {
            0.0
        }
    }

    /// Its solid angle.
    pub fn solid_angle(&self) -> f32 {
        2.0 * PI * self.cap
    }
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
            EnvironmentDesc::Sun {
                direction,
                radiance,
                half_angle,
            } => Environment::Sun(SunDisk {
                frame: Frame::from_normal(direction.normalize()),
                radiance: *radiance,
                cap: (1.0 - (*half_angle as f64).cos()) as f32,
            }),
        }
    }

    /// Whether a strategy that does not aim at this light (BSDF sampling, or sampling the
    /// openings light comes through) finds it too rarely to carry it: the sun.
    pub fn is_compact(&self) -> bool {
        matches!(self, Environment::Sun(_))
    }

    /// The sun's disk, if this is one.
    pub fn sun(&self) -> Option<&SunDisk> {
        match self {
            Environment::Sun(s) => Some(s),
            _ => None,
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
            Environment::Sun(s) if s.holds(dir.normalize()) => s.radiance,
            Environment::Sun(_) => Rgb::ZERO,
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
            Environment::Sun(s) => {
                return Some(LightSample {
                    wi: s.sample(u),
                    li: s.radiance,
                    pdf: warp::uniform_cone_pdf(s.cap),
                    point: None,
                    delta: false,
                })
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
            Environment::Sun(s) => s.pdf(dir),
        }
    }

    /// Power through the scene's bounding disk (pbrt-v4's convention).
    pub fn power(&self, scene: &Scene) -> f32 {
        let r = scene.bounding_sphere().1;
        let mean = match self {
            Environment::Constant(l) => l.luminance(),
            Environment::Image(e) => (e.image.mean() * e.scale).luminance(),
            // Its radiance times its solid angle, spread over the sphere.
            Environment::Sun(s) => s.radiance.luminance() * s.solid_angle() / (4.0 * PI),
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

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Rng;

    #[test]
    fn the_suns_samples_cover_its_disk_and_nothing_else() {
        let half_angle = 0.2666f32.to_radians();
        let direction = Vec3::new(0.3, -0.5, 0.8).normalize();
        let sun = Environment::new(&EnvironmentDesc::Sun {
            direction,
            radiance: Rgb::splat(1e6),
            half_angle,
        });
        let mut rng = Rng::new(3);
        // Every sample lies on the disk, with the density pdf_li gives it.
        for _ in 0..10_000 {
            let s = sun.sample_li(rng.next_2d()).expect("a sample");
            assert_eq!(sun.le(s.wi), Rgb::splat(1e6));
            assert!((sun.pdf_li(s.wi) / s.pdf - 1.0).abs() < 1e-6);
        }
        // The disk le and pdf_li see has the solid angle the density integrates to one over:
        // uniform directions in a cone four times as wide land on it 1/16 of the time.
        let wide = 4.0 * half_angle;
        let cap = 1.0 - (wide as f64).cos();
        let frame = Frame::from_normal(direction);
        let n = 400_000;
        let (mut on, mut pdf_sum) = (0u32, 0.0f64);
        for _ in 0..n {
            let d = frame.to_world(warp::square_to_uniform_cone(rng.next_2d(), cap as f32));
            if !sun.le(d).is_black() {
                on += 1;
            }
            pdf_sum += sun.pdf_li(d) as f64;
        }
        let share = on as f64 / n as f64;
        let expect = (1.0 - (half_angle as f64).cos()) / cap;
        let se = (expect * (1.0 - expect) / n as f64).sqrt();
        assert!((share - expect).abs() < 4.0 * se, "{share} vs {expect}");
        // Integral of pdf_li over the wide cone: one.
        let integral = pdf_sum / n as f64 * 2.0 * std::f64::consts::PI * cap;
        assert!((integral - 1.0).abs() < 4.0 * se / expect, "{integral}");
        assert_eq!(sun.le(-direction), Rgb::ZERO);
        assert_eq!(sun.pdf_li(-direction), 0.0);
    }
}
