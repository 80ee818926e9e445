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
use fenestra_scene::{Material, Scene, SurfaceInteraction};
use light::{LightSampler, Lights, PowerLightSampler, UniformLightSampler};
use std::borrow::Cow;

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
