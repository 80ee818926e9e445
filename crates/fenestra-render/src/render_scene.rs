//! A scene ready to render: the scene's geometry with one BSDF per material and its lights
//! in samplable form. Light selection is not here: an integrator owns its light sampler.

use crate::bsdf::{self, Bsdf};
use crate::light::Lights;
use fenestra_core::{Ray, Rgb};
use fenestra_scene::material;
use fenestra_scene::{Material, Scene, SurfaceInteraction};
use glam::Mat3;
use std::borrow::Cow;

/// Panes a ray passes before it counts as blocked.
const MAX_PANES: usize = 16;

/// A scene with what rendering needs besides geometry: BSDFs and samplable lights.
pub struct RenderScene {
    /// Geometry, materials, camera and ray queries.
    pub scene: Scene,
    /// One BSDF per material of `scene`, same order.
    pub bsdfs: Vec<Bsdf>,
    /// Every light, emissive shapes included.
    pub lights: Lights,
    /// Whether any material is thin glass: without it a visibility ray is an any-hit query.
    thin_glass: bool,
    /// Whether any material is smooth glass (which probes may follow by refraction).
    smooth_glass: bool,
    /// Whether any surface emits: without it a ray looking for emission needs only to know
    /// whether it leaves the scene.
    surface_lights: bool,
    /// What the film does to every sample (the camera's white balance), made once.
    sensor_response: Option<Mat3>,
}

impl RenderScene {
    /// Builds the BSDFs and lights of `scene`.
    pub fn new(scene: Scene) -> Self {
        // A mix stands for its first material where one BSDF per material is asked for
        // (photon tracing's transmissive test); `bsdf_at` resolves it at each point.
        let mut bsdfs: Vec<Bsdf> = Vec::with_capacity(scene.materials.len());
        for m in &scene.materials {
            let b = match m {
                Material::Mix(material::Mix { materials, .. }) => bsdfs[materials[0]].clone(),
                m => Bsdf::from_material(m),
            };
            bsdfs.push(b);
        }
        let lights = Lights::new(&scene);
        let thin_glass = bsdfs.iter().any(|b| matches!(b, Bsdf::ThinDielectric(_)));
        let smooth_glass = bsdfs.iter().any(|b| matches!(b, Bsdf::SmoothDielectric(_)));
        let surface_lights = lights.first_area_light.iter().any(Option::is_some);
        let sensor_response = scene.camera.sensor_response();
        RenderScene {
            scene,
            bsdfs,
            lights,
            thin_glass,
            smooth_glass,
            surface_lights,
            sensor_response,
        }
    }

    /// What the film does to every sample's linear sRGB (the camera's white balance), if
    /// anything.
    pub fn sensor_response(&self) -> Option<Mat3> {
        self.sensor_response
    }

    /// Whether any material is thin glass (visibility then follows rays through panes).
    pub fn has_thin_glass(&self) -> bool {
        self.thin_glass
    }

    /// Whether any material is smooth glass (a refracting interface).
    pub fn has_smooth_glass(&self) -> bool {
        self.smooth_glass
    }

    /// Whether any surface emits (else only environments light what rays escape to).
    pub fn has_surface_lights(&self) -> bool {
        self.surface_lights
    }

    /// Follows a ray through thin glass panes (pbrt's "thindielectric", windows): each pane
    /// lets the fraction 1 - R' of the light through along the same line. Returns that
    /// transmittance and the first other surface met before `tmax` (`None`: nothing but
    /// panes in the way). Visibility rays of next-event estimation use it, and path tracing
    /// counts no vertex for the straight-through part, so both techniques see the same
    /// light (MIS stays consistent).
    pub fn through_glass(&self, mut ray: Ray, mut tmax: f32) -> (Rgb, Option<SurfaceInteraction>) {
        if !self.thin_glass {
            let hit = self.scene.intersect(&ray, tmax);
            return (Rgb::ONE, hit.map(|hit| self.scene.interaction(&ray, &hit)));
        }
        let mut tr = Rgb::ONE;
        for _ in 0..MAX_PANES {
            let Some(hit) = self.scene.intersect(&ray, tmax) else {
                return (tr, None);
            };
            let si = self.scene.interaction(&ray, &hit);
            let Bsdf::ThinDielectric(pane) = &self.bsdfs[self.material_at(&si)] else {
                return (tr, Some(si));
            };
            tr *= 1.0 - pane.reflectance(si.ng.dot(ray.d));
            ray = Ray::new(si.spawn(ray.d), ray.d);
            tmax -= hit.t;
        }
        (Rgb::ZERO, None)
    }

    /// Transmittance of the segment from the ray's origin to `tmax` (zero when anything but
    /// thin glass blocks it).
    pub fn transmittance(&self, ray: Ray, tmax: f32) -> Rgb {
        if !self.thin_glass {
            return if self.scene.occluded(&ray, tmax) {
                Rgb::ZERO
            } else {
                Rgb::ONE
            };
        }
        match self.through_glass(ray, tmax) {
            (tr, None) => tr,
            (_, Some(_)) => Rgb::ZERO,
        }
    }

    /// The BSDF at a surface point: the material's, with textured parameters looked up at
    /// the point's uv.
    pub fn bsdf_at(&self, si: &SurfaceInteraction) -> Cow<'_, Bsdf> {
        let material = self.material_at(si);
        match &self.scene.materials[material] {
            // Clamped to [0, 1] as pbrt-v4 clamps reflectances (a scaled texture may exceed 1).
            Material::TexturedDiffuse(material::TexturedDiffuse { texture }) => {
                Cow::Owned(Bsdf::Diffuse(bsdf::Diffuse {
                    reflectance: texture.lookup(si.uv).map(|c| c.clamp(0.0, 1.0)),
                }))
            }
            Material::RoughConductor(material::RoughConductor {
                eta,
                k,
                alpha_x,
                alpha_y,
                roughness: Some(map),
            }) => {
                let (ax, ay) = map.alphas(si.uv, (*alpha_x, *alpha_y));
                Cow::Owned(Bsdf::RoughConductor(bsdf::RoughConductor::new(
                    *eta, *k, ax, ay,
                )))
            }
            Material::CoatedDiffuse(material::CoatedDiffuse {
                texture: Some(texture),
                ..
            }) => match &self.bsdfs[material] {
                Bsdf::Layered(b) => Cow::Owned(Bsdf::Layered(
                    b.with_base_reflectance(texture.lookup(si.uv)),
                )),
                other => Cow::Borrowed(other),
            },
            Material::MetallicRoughness(m) if m.is_textured() => Cow::Owned(
                Bsdf::MetallicRoughness(bsdf::MetallicRoughness::of(m, m.at(si.uv))),
            ),
            _ => Cow::Borrowed(&self.bsdfs[material]),
        }
    }

    /// The material index at a surface point, mixes resolved.
    fn material_at(&self, si: &SurfaceInteraction) -> usize {
        Material::resolve(
            &self.scene.materials,
            self.scene.shapes[si.shape].material,
            si.p,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::image::Image;
    use fenestra_core::{Vec2, Vec3};
    use fenestra_scene::texture::{ImageTexture, RoughnessTexture};
    use fenestra_scene::{
        Backend, Camera, RenderDefaults, SceneDesc, Shape, ShapeKind, TriangleMesh,
    };
    use std::sync::Arc;

    /// A conductor whose roughness image is 0.01 on its left half and 0.25 on its right: the
    /// BSDF at a hit is the conductor of the texel's alpha (remapped: 0.1 and 0.5).
    #[test]
    fn rough_conductors_look_their_roughness_up_at_each_hit() {
        let mut img = Image::new(2, 1);
        img.set(0, 0, Rgb::splat(0.01));
        img.set(1, 0, Rgb::splat(0.25));
        let texture = Arc::new(ImageTexture::new(Arc::new(img), "r.exr".into()));
        let (eta, k) = (Rgb::new(0.2, 0.9, 1.1), Rgb::new(3.9, 2.4, 2.1));
        let material = |alpha: f32, roughness| {
            Material::RoughConductor(material::RoughConductor {
                eta,
                k,
                alpha_x: alpha,
                alpha_y: alpha,
                roughness,
            })
        };
        let map = RoughnessTexture {
            u: Some(texture.clone()),
            v: Some(texture),
            remap: true,
        };
        let desc = SceneDesc {
            name: "plate".into(),
            shapes: vec![Shape::new(
                ShapeKind::Mesh(TriangleMesh::quad(Vec3::ZERO, Vec3::X, Vec3::Y)),
                0,
            )],
            materials: vec![material(0.3, Some(Arc::new(map)))],
            lights: vec![],
            camera: Camera::look_at(Vec3::Z * 3.0, Vec3::ZERO, Vec3::Y, 60.0).expect("camera"),
            defaults: RenderDefaults::default(),
            portals: Vec::new(),
        };
        let scene = RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"));
        let (wo, wi) = (
            Vec3::new(0.3, 0.1, 0.95).normalize(),
            Vec3::new(-0.25, -0.1, 0.96).normalize(),
        );
        // x = -0.5 is u = 0.25 (the left texel), x = 0.5 is u = 0.75.
        for (x, alpha) in [(-0.5, 0.1), (0.5, 0.5)] {
            let ray = Ray::new(Vec3::new(x, 0.0, 1.0), -Vec3::Z);
            let hit = scene.scene.intersect(&ray, 10.0).expect("hit");
            let si = scene.scene.interaction(&ray, &hit);
            assert!(
                (si.uv - Vec2::new(0.5 * (x + 1.0), 0.5)).length() < 1e-5,
                "{:?}",
                si.uv
            );
            let want = Bsdf::from_material(&material(alpha, None)).eval(wo, wi);
            let got = scene.bsdf_at(&si).eval(wo, wi);
            assert!(
                (got - want).map(f32::abs).max_component() < 1e-4 * want.max_component(),
                "x {x}: {got:?} vs {want:?}"
            );
        }
    }
}
