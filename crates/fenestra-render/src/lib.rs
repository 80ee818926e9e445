//! Rendering for fenestra: BSDFs, lights and light selection, the film, integrators and
//! render statistics. Research systems plug in through [`integrator::Integrator`] and
//! [`light::LightSampler`].

pub mod bsdf;
pub mod film;
pub mod integrator;
pub mod light;
pub mod output;
pub mod portal;
pub mod stats;

pub use film::Film;
pub use integrator::{Integrator, RenderControl, RenderSettings};
pub use stats::RenderStats;

use bsdf::Bsdf;
use fenestra_core::ray::offset_origin;
use fenestra_core::{Ray, Rgb};
use fenestra_scene::Hit;
use fenestra_scene::{Material, Scene, SurfaceInteraction};
use light::{LightSampler, Lights, PowerLightSampler, UniformLightSampler};
use std::borrow::Cow;

/// Panes a ray passes before it counts as blocked.
const MAX_PANES: usize = 16;

/// How lights are chosen for next-event estimation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum LightSelection {
    Uniform,
    Power,
}

impl std::str::FromStr for LightSelection {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "uniform" => Ok(LightSelection::Uniform),
            "power" => Ok(LightSelection::Power),
            _ => Err(format!(
                "unknown light selection '{s}' (expected uniform or power)"
            )),
        }
    }
}

/// A scene ready to render: geometry, one BSDF per material, lights and a light sampler.
pub struct RenderScene {
    pub scene: Scene,
    pub bsdfs: Vec<Bsdf>,
    pub lights: Lights,
    pub light_sampler: Box<dyn LightSampler>,
}

impl RenderScene {
    pub fn new(scene: Scene, selection: LightSelection) -> Self {
        let bsdfs = scene.materials.iter().map(Bsdf::from_material).collect();
        let lights = Lights::new(&scene);
        let light_sampler: Box<dyn LightSampler> = match selection {
            LightSelection::Uniform => Box::new(UniformLightSampler::new(&lights)),
            LightSelection::Power => Box::new(PowerLightSampler::new(&scene, &lights)),
        };
        RenderScene {
            scene,
            bsdfs,
            lights,
            light_sampler,
        }
    }

    /// Follows a ray through thin glass panes (pbrt's "thindielectric", windows): each pane
    /// lets the fraction 1 - R' of the light through along the same line. Returns that
    /// transmittance and the first other surface hit before `tmax` (`None`: nothing but
    /// panes in the way). Shadow and portal rays use it, and path tracing counts no vertex
    /// for the straight-through part, so both techniques see the same light (MIS stays
    /// consistent).
    pub fn through_glass(&self, mut ray: Ray, mut tmax: f32) -> (Rgb, Option<Hit>) {
        let mut tr = Rgb::ONE;
        for _ in 0..MAX_PANES {
            let Some(hit) = self.scene.intersect(&ray, tmax) else {
                return (tr, None);
            };
            let Bsdf::ThinDielectric(pane) =
                &self.bsdfs[self.scene.shapes[hit.shape as usize].material]
            else {
                return (tr, Some(hit));
            };
            let si = self.scene.interaction(&ray, &hit);
            tr *= 1.0 - pane.reflectance(si.ng.dot(ray.d));
            ray = Ray::new(offset_origin(si.p, si.ng, ray.d), ray.d);
            tmax -= hit.t;
        }
        (Rgb::ZERO, None)
    }

    /// Transmittance of the segment from the ray's origin to `tmax` (zero when anything but
    /// thin glass blocks it).
    pub fn transmittance(&self, ray: Ray, tmax: f32) -> Rgb {
        match self.through_glass(ray, tmax) {
            (tr, None) => tr,
            (_, Some(_)) => Rgb::ZERO,
        }
    }

    /// The BSDF at a surface point: the material's, with textured reflectance looked up at
    /// the point's uv.
    pub fn bsdf_at(&self, si: &SurfaceInteraction) -> Cow<'_, Bsdf> {
        let material = self.scene.shapes[si.shape].material;
        match &self.scene.materials[material] {
            Material::TexturedDiffuse { texture } => Cow::Owned(Bsdf::Diffuse(bsdf::Diffuse {
                reflectance: texture.lookup(si.uv),
            })),
            _ => Cow::Borrowed(&self.bsdfs[material]),
        }
    }
}
