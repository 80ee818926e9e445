//! Samplable lights built from the scene's light descriptions and emissive shapes.

mod area;
mod auto;
mod distant;
mod environment;
pub mod learning;
mod point;
pub mod probe;
pub mod sampler;
mod spot;

pub use area::AreaLight;
pub use auto::{AutoLightSampler, SPLIT_MARGIN};
pub use distant::DistantLight;
pub use environment::{Environment, SunDisk};
pub use learning::{LightRecord, LightRecords};
pub use point::PointLight;
pub use sampler::{
    LightContext, LightOptions, LightSampler, LightSelection, Picks, PowerLightSampler,
    SplitLightSampler, SplitSuns, UniformLightSampler, MAX_PICKS,
};
pub use spot::SpotLight;

use fenestra_core::{Rgb, Vec2, Vec3};
use fenestra_scene::{Emission, LightDesc, Scene, ShapeKind, SurfaceInteraction};

/// Incident light sampled at a point.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit direction from the shading point towards the light.
    pub wi: Vec3,
    /// Incident radiance (for delta lights, the irradiance-like quantity I/d^2 or E).
    pub li: Rgb,
    /// Solid-angle density (1 for delta lights).
    pub pdf: f32,
    /// Point on the light, or `None` at infinity.
    pub point: Option<Vec3>,
    /// Dirac light (point, spot, distant): cannot be hit by BSDF sampling, no MIS.
    pub delta: bool,
}

impl LightSample {
    /// The sample of a light picked with probability `pick`: its density times `pick`.
    pub fn picked(self, pick: f32) -> Self {
        LightSample {
            pdf: self.pdf * pick,
            ..self
        }
    }
}

/// A ray leaving a light (for photon tracing): origin, unit direction and the power it
/// carries.
#[derive(Clone, Copy, Debug)]
pub struct EmittedRay {
    /// Where it starts.
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
    /// Emitted radiance (or intensity, or irradiance) along the ray over the density of
    /// its origin and direction: a photon's power, before dividing by the probability of
    /// picking the light. Its mean over the light's rays is the light's power.
    pub power: Rgb,
}

/// A ray from outside the scene travelling along `dir` (lights at infinity) towards the
/// sphere `aim` (centre, radius): its origin is uniform on the disk of the sphere's radius
/// facing `dir`, moved back along `dir` until it lies outside the scene's bounding sphere;
/// `irradiance` is the light's across the disk (over the density of `dir`).
fn ray_from_infinity(
    scene: &Scene,
    (center, radius): (Vec3, f32),
    dir: Vec3,
    irradiance: Rgb,
    u: Vec2,
) -> EmittedRay {
    let (scene_center, scene_radius) = scene.bounding_sphere();
    let back = scene_radius + (center - scene_center).length();
    let d = fenestra_core::warp::square_to_disk_concentric(u) * radius;
    let offset = fenestra_core::Frame::from_normal(dir).to_world(Vec3::new(d.x, d.y, 0.0));
    EmittedRay {
        origin: center - dir * back + offset,
        dir,
        power: irradiance * (std::f32::consts::PI * radius * radius),
    }
}

/// Unit direction from `p` to a point light at `position` and the squared distance, or
/// `None` when they coincide.
fn toward(position: Vec3, p: Vec3) -> Option<(Vec3, f32)> {
    let d = position - p;
    let d2 = d.length_squared();
    (d2 > 0.0).then(|| (d / d2.sqrt(), d2))
}

/// Where a ray met a light: on an emitting surface, or nowhere (it escaped to the
/// environment).
#[derive(Clone, Copy, Debug)]
pub enum LightHit<'a> {
    /// The ray hit an emitting surface here.
    Surface(&'a SurfaceInteraction),
    /// The ray left the scene.
    Escaped,
}

/// A light of any kind.
#[derive(Clone, Debug)]
pub enum Light {
    /// Point light.
    Point(PointLight),
    /// Spot light.
    Spot(SpotLight),
    /// Directional light.
    Distant(DistantLight),
    /// Emissive shape.
    Area(AreaLight),
    /// Environment.
    Environment(Environment),
}

impl Light {
    /// Samples a direction from `p` towards the light: incident radiance, density, point.
    pub fn sample_li(&self, scene: &Scene, p: Vec3, u: Vec2) -> Option<LightSample> {
        match self {
            Light::Point(l) => l.sample_li(p),
            Light::Spot(l) => l.sample_li(p),
            Light::Distant(l) => l.sample_li(),
            Light::Area(l) => l.sample_li(scene, p, u),
            Light::Environment(l) => l.sample_li(u),
        }
    }

    /// Radiance arriving along the direction `wi` (pointing from the receiver towards the
    /// light) from this light, met at `hit`; zero where the light is not (and always for
    /// Dirac lights, which no ray meets).
    pub fn le(&self, hit: LightHit, wi: Vec3) -> Rgb {
        match (self, hit) {
            (Light::Area(a), LightHit::Surface(si)) => a.le(si, -wi),
            (Light::Environment(e), LightHit::Escaped) => e.le(wi),
            _ => Rgb::ZERO,
        }
    }

    /// Solid-angle density with which [`Light::sample_li`] at `p` gives the direction `wi`
    /// that meets the light at `hit` (zero for Dirac lights and where the light is not).
    pub fn pdf_li(&self, scene: &Scene, p: Vec3, wi: Vec3, hit: LightHit) -> f32 {
        match (self, hit) {
            (Light::Area(a), LightHit::Surface(si)) => a.pdf_li(scene, p, si),
            (Light::Environment(e), LightHit::Escaped) => e.pdf_li(wi),
            _ => 0.0,
        }
    }

    /// Solid-angle density with which [`Light::sample_li`] gives the direction `wi` towards
    /// a light at infinity, a Dirac direction counting 1 (as the densities of light paths'
    /// MIS count it); 0 for lights at a finite distance.
    pub fn pdf_at_infinity(&self, wi: Vec3) -> f32 {
        match self {
            Light::Distant(_) => 1.0,
            Light::Environment(e) => e.pdf_li(wi),
            _ => 0.0,
        }
    }

    /// A ray leaving the light: a point on it from `u_pos`, a direction from `u_dir`
    /// (uniform for point lights, within the cone for spots, cosine-weighted for area
    /// emitters, importance-sampled for environments). Used by photon tracing.
    pub fn sample_ray(&self, scene: &Scene, u_pos: Vec2, u_dir: Vec2) -> Option<EmittedRay> {
        self.sample_ray_aimed(scene, scene.bounding_sphere(), u_pos, u_dir)
    }

    /// [`Light::sample_ray`] with the rays of lights at infinity aimed at the sphere `aim`
    /// (centre, radius) instead of the whole scene; their power is then that through the
    /// sphere's disk.
    pub fn sample_ray_aimed(
        &self,
        scene: &Scene,
        aim: (Vec3, f32),
        u_pos: Vec2,
        u_dir: Vec2,
    ) -> Option<EmittedRay> {
        match self {
            Light::Point(l) => Some(EmittedRay {
                origin: l.position(),
                dir: fenestra_core::warp::square_to_uniform_sphere(u_dir),
                power: l.intensity() * (4.0 * std::f32::consts::PI),
            }),
            Light::Spot(l) => Some(l.sample_ray(u_dir)),
            Light::Distant(l) => Some(ray_from_infinity(
                scene,
                aim,
                l.direction(),
                l.irradiance(),
                u_pos,
            )),
            Light::Area(l) => l.sample_ray(scene, u_pos, u_dir),
            Light::Environment(l) => {
                let s = l.sample_li(u_dir)?;
                (s.pdf > 0.0).then(|| ray_from_infinity(scene, aim, -s.wi, s.li / s.pdf, u_pos))
            }
        }
    }

    /// Whether the light lies at infinity (directional lights and environments).
    pub fn at_infinity(&self) -> bool {
        matches!(self, Light::Distant(_) | Light::Environment(_))
    }

    /// Whether a strategy that does not aim at this light (BSDF sampling, or sampling the
    /// openings light comes through) finds it never or too rarely to carry it: Dirac lights
    /// and the sun, which keep their own light sampling where such a strategy takes the rest.
    pub fn is_compact(&self) -> bool {
        match self {
            Light::Point(_) | Light::Spot(_) | Light::Distant(_) => true,
            Light::Area(_) => false,
            Light::Environment(e) => e.is_compact(),
        }
    }

    /// Total emitted power (luminance of watts), for power-proportional light selection.
    pub fn power(&self, scene: &Scene) -> f32 {
        match self {
            Light::Point(l) => l.power(),
            Light::Spot(l) => l.power(),
            Light::Distant(l) => l.power(scene),
            Light::Area(l) => l.power(),
            Light::Environment(l) => l.power(scene),
        }
    }
}

/// All lights of a scene, with the maps the integrators need.
pub struct Lights {
    /// Every light: the scene's lights first, then one per emissive triangle, sphere and
    /// disk, shape by shape.
    pub lights: Vec<Light>,
    /// For each shape that emits, the index of the light of its primitive 0; primitive k's
    /// light follows k places later.
    pub first_area_light: Vec<Option<usize>>,
    /// Indices of environment lights (seen by rays that escape).
    pub environments: Vec<usize>,
    /// Whether any light is compact (see [`Light::is_compact`]).
    pub has_compact: bool,
}

impl Lights {
    /// The lights of `scene`.
    pub fn new(scene: &Scene) -> Self {
        let mut lights = Vec::new();
        let mut environments = Vec::new();
        for desc in &scene.lights {
            let light = match desc {
                LightDesc::Point {
                    position,
                    intensity,
                } => Light::Point(PointLight::new(*position, *intensity)),
                LightDesc::Spot {
                    position,
                    direction,
                    intensity,
                    cone_angle,
                    falloff_start,
                } => Light::Spot(SpotLight::new(
                    *position,
                    *direction,
                    *intensity,
                    *cone_angle,
                    *falloff_start,
                )),
                LightDesc::Distant {
                    direction,
                    irradiance,
                } => Light::Distant(DistantLight::new(*direction, *irradiance)),
                LightDesc::Environment(env) => {
                    environments.push(lights.len());
                    Light::Environment(Environment::new(env))
                }
            };
            lights.push(light);
        }
        let first_area_light = scene
            .shapes
            .iter()
            .enumerate()
            .map(|(i, s)| {
                // An emitter without area (an empty mesh) emits nothing.
                let emits = |e: &Emission| !e.radiance.is_black() && s.area() > 0.0;
                s.emission.filter(emits).map(|e| {
                    let first = lights.len();
                    let prims = match &s.kind {
                        ShapeKind::Mesh(m) => m.indices.len(),
                        _ => 1,
                    };
                    for prim in 0..prims {
                        lights.push(Light::Area(AreaLight::new(scene, i, prim, e)));
                    }
                    first
                })
            })
            .collect();
        let has_compact = lights.iter().any(Light::is_compact);
        Lights {
            lights,
            first_area_light,
            environments,
            has_compact,
        }
    }

    /// The area light of the surface hit at `si`, if it emits, and its radiance arriving
    /// along `wi` (zero on its back side).
    pub fn surface_emission(&self, si: &SurfaceInteraction, wi: Vec3) -> Option<(usize, Rgb)> {
        let i = self.first_area_light[si.shape]? + si.prim;
        Some((i, self.lights[i].le(LightHit::Surface(si), wi)))
    }
}
