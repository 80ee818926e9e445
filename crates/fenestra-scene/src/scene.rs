//! A validated scene with its ray-query structure.

use crate::accel::{Backend, Hit, RayQuery, PACKET};
use crate::camera::Camera;
use crate::interaction::SurfaceInteraction;
use crate::light::{EnvironmentDesc, LightDesc};
use crate::material;
use crate::material::Material;
use crate::shape::{Shape, ShapeKind};
use fenestra_core::{Ray, Vec3};

/// Render settings a scene proposes (a scene file's Film, Sampler and Integrator).
#[derive(Clone, Debug)]
pub struct RenderDefaults {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Maximum path length in segments from the camera to the emitter (2 = direct light).
    pub max_depth: u32,
    /// Integrator options the scene file sets (option key and its value as text, e.g.
    /// `light.selection` = `bvh` from a pbrt-v4 Integrator directive): a render takes them
    /// where its integrator reads them and the command line does not set them.
    pub options: Vec<(String, String)>,
}

impl Default for RenderDefaults {
    fn default() -> Self {
        RenderDefaults {
            width: 512,
            height: 512,
            spp: 64,
            max_depth: 8,
            options: Vec::new(),
        }
    }
}

/// Everything a scene is made of, before it is validated and gets its acceleration structure.
#[derive(Clone, Debug)]
pub struct SceneDesc {
    /// The scene's name (a built-in's, or the file's stem).
    pub name: String,
    /// Every shape, emitters included.
    pub shapes: Vec<Shape>,
    /// Materials, indexed by `Shape::material`.
    pub materials: Vec<Material>,
    /// Lights that are not shapes (area emitters are shapes with an emission).
    pub lights: Vec<LightDesc>,
    /// The camera.
    pub camera: Camera,
    /// Render settings the scene proposes.
    pub defaults: RenderDefaults,
    /// Light portals given by the scene (pbrt-v4's "point3 portal" of an infinite light):
    /// planar quads, corners in order.
    pub portals: Vec<[Vec3; 4]>,
}

impl SceneDesc {
    /// The same scene with every length multiplied by `s` about the origin (a change of
    /// units): geometry, camera, lights and portals move and grow, radiance stays, and point
    /// and spot intensities grow by s^2 so that the picture is the same.
    pub fn scaled(mut self, s: f32) -> SceneDesc {
        for shape in &mut self.shapes {
            match &mut shape.kind {
                ShapeKind::Mesh(m) => m.positions.iter_mut().for_each(|p| *p *= s),
                ShapeKind::Sphere { center, radius } | ShapeKind::Disk { center, radius, .. } => {
                    *center *= s;
                    *radius *= s;
                }
            }
        }
        for light in &mut self.lights {
            match light {
                LightDesc::Point {
                    position,
                    intensity,
                }
                | LightDesc::Spot {
                    position,
                    intensity,
                    ..
                } => {
                    *position *= s;
                    *intensity *= s * s;
                }
                LightDesc::Distant { .. } | LightDesc::Environment(_) => {}
            }
        }
        self.camera.position *= s;
        self.portals
            .iter_mut()
            .for_each(|quad| quad.iter_mut().for_each(|p| *p *= s));
        self
    }

    /// The same scene with every emitter `k` times as bright: the image a camera exposed `k`
    /// times as long (or as sensitive) takes. Light transport is linear in the emitters, and
    /// light sampling by power is unchanged by a common factor, so the render is the same
    /// paths with `k` times their values.
    pub fn exposed(mut self, k: f32) -> SceneDesc {
        for e in self.shapes.iter_mut().filter_map(|s| s.emission.as_mut()) {
            e.radiance *= k;
        }
        for light in &mut self.lights {
            match light {
                LightDesc::Point { intensity, .. } | LightDesc::Spot { intensity, .. } => {
                    *intensity *= k
                }
                LightDesc::Distant { irradiance, .. } => *irradiance *= k,
                LightDesc::Environment(EnvironmentDesc::Constant(radiance))
                | LightDesc::Environment(EnvironmentDesc::Sun { radiance, .. }) => *radiance *= k,
                LightDesc::Environment(EnvironmentDesc::Image { scale, .. }) => *scale *= k,
            }
        }
        self
    }
}

/// The cut-out of a material, if it has one.
fn cutout(m: &Material) -> Option<&material::Alpha> {
    match m {
        Material::MetallicRoughness(m) => m.alpha.as_ref(),
        _ => None,
    }
}

/// Why a scene description is not a valid scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// A shape names a material that does not exist.
    #[error("shape {shape}: material index {material} out of range ({count} materials)")]
    MaterialIndex {
        /// The shape.
        shape: usize,
        /// The material index it names.
        material: usize,
        /// How many materials there are.
        count: usize,
    },
    /// A triangle names a vertex that does not exist.
    #[error(
        "shape {shape}: triangle {triangle} uses vertex {vertex} but the mesh has {count} vertices"
    )]
    VertexIndex {
        /// The shape.
        shape: usize,
        /// The triangle.
        triangle: usize,
        /// The vertex index it names.
        vertex: u32,
        /// How many vertices the mesh has.
        count: usize,
    },
    /// A shape's geometry is invalid.
    #[error("shape {shape}: {what}")]
    Geometry {
        /// The shape.
        shape: usize,
        /// What is wrong.
        what: String,
    },
    /// A material's parameters are invalid.
    #[error("material {index}: {what}")]
    Material {
        /// The material.
        index: usize,
        /// What is wrong.
        what: String,
    },
    /// A light's parameters are invalid.
    #[error("light {index}: {what}")]
    Light {
        /// The light.
        index: usize,
        /// What is wrong.
        what: String,
    },
    /// The ray-query library refused the geometry.
    #[cfg(feature = "embree")]
    #[error("building the ray-query structure failed: {0}")]
    Accel(#[from] crate::accel::EmbreeError),
}

/// A validated scene with its ray-query structure: what renderers read.
pub struct Scene {
    /// The scene's name.
    pub name: String,
    /// Every shape, emitters included.
    pub shapes: Vec<Shape>,
    /// Materials, indexed by `Shape::material`.
    pub materials: Vec<Material>,
    /// Lights that are not shapes.
    pub lights: Vec<LightDesc>,
    /// The camera.
    pub camera: Camera,
    /// Render settings the scene proposes.
    pub defaults: RenderDefaults,
    /// Light portals given by the scene (quads, corners in order).
    pub portals: Vec<[Vec3; 4]>,
    /// The ray-query backend in use.
    pub backend: Backend,
    accel: Box<dyn RayQuery>,
    bounds: (Vec3, Vec3),
    /// Whether the meshes outgrow a core's cache, so that [`Scene::prefetch_hits`] pays.
    large: bool,
    /// Whether any shape's material has cut-outs (then every ray query looks through them).
    cutouts: bool,
}

/// Cut-out surfaces a ray passes before the query gives up and takes the next as solid.
const MAX_CUTOUT_LAYERS: usize = 64;

/// Mesh data (triangles' indices and vertices) beyond which hits are prefetched: about a
/// core's L2 cache. Below it the data stays cached and prefetching costs 1-2% (measured).
const PREFETCH_ABOVE_BYTES: usize = 1 << 20;

impl Scene {
    /// Validates `desc` and builds its ray-query structure with `backend`.
    pub fn build(desc: SceneDesc, backend: Backend) -> Result<Scene, SceneError> {
        validate(&desc)?;
        let accel = backend.build(&desc.shapes)?;
        let cutouts = desc
            .shapes
            .iter()
            .any(|s| cutout(&desc.materials[s.material]).is_some());
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for s in &desc.shapes {
            for p in 0..s.primitive_count() {
                let (a, b) = s.primitive_bounds(p);
                lo = lo.min(a);
                hi = hi.max(b);
            }
        }
        if lo.x > hi.x {
            (lo, hi) = (Vec3::ZERO, Vec3::ZERO);
        }
        let mesh_bytes: usize = desc
            .shapes
            .iter()
            .map(|s| match &s.kind {
                ShapeKind::Mesh(m) => m.bytes(),
                _ => 0,
            })
            .sum();
        Ok(Scene {
            name: desc.name,
            shapes: desc.shapes,
            materials: desc.materials,
            lights: desc.lights,
            camera: desc.camera,
            defaults: desc.defaults,
            portals: desc.portals,
            backend,
            accel,
            bounds: (lo, hi),
            large: mesh_bytes > PREFETCH_ABOVE_BYTES,
            cutouts,
        })
    }

    /// The closest hit along `ray` in (0, tmax) (cut-outs passed through).
    pub fn intersect(&self, ray: &Ray, tmax: f32) -> Option<Hit> {
        match self.cutouts {
            false => self.accel.intersect(ray, tmax),
            true => self.through_cutouts(ray, tmax),
        }
    }

    /// Whether anything lies along `ray` in (0, tmax) (cut-outs passed through).
    pub fn occluded(&self, ray: &Ray, tmax: f32) -> bool {
        match self.cutouts {
            false => self.accel.occluded(ray, tmax),
            true => self.through_cutouts(ray, tmax).is_some(),
        }
    }

    /// [`Scene::intersect`] of eight rays by one packet query.
    pub fn intersect8(&self, rays: &[Ray; PACKET], tmax: [f32; PACKET]) -> [Option<Hit>; PACKET] {
        match self.cutouts {
            false => self.accel.intersect8(rays, tmax),
            true => std::array::from_fn(|i| self.through_cutouts(&rays[i], tmax[i])),
        }
    }

    /// [`Scene::occluded`] of eight rays by one packet query.
    pub fn occluded8(&self, rays: &[Ray; PACKET], tmax: [f32; PACKET]) -> [bool; PACKET] {
        match self.cutouts {
            false => self.accel.occluded8(rays, tmax),
            true => std::array::from_fn(|i| self.through_cutouts(&rays[i], tmax[i]).is_some()),
        }
    }

    /// The closest hit along `ray` in (0, tmax) where the surface is present: at a cut-out,
    /// the ray goes on from just beyond it (its hit's `t` stays on the original ray).
    fn through_cutouts(&self, ray: &Ray, tmax: f32) -> Option<Hit> {
        let (mut cur, mut travelled) = (*ray, 0.0f32);
        for layer in 0..MAX_CUTOUT_LAYERS {
            let mut hit = self.accel.intersect(&cur, tmax - travelled)?;
            let shape = &self.shapes[hit.shape as usize];
            let solid = |si: &SurfaceInteraction, alpha: &material::Alpha| {
                layer + 1 == MAX_CUTOUT_LAYERS || alpha.present(si.uv, si.p)
            };
            let through = match cutout(&self.materials[shape.material]) {
                None => None,
                Some(alpha) => {
                    let si = SurfaceInteraction::from_hit(shape, &cur, &hit);
                    (!solid(&si, alpha)).then(|| si.spawn(cur.d))
                }
            };
            let Some(origin) = through else {
                hit.t += travelled;
                return Some(hit);
            };
            travelled = (origin - ray.o).dot(ray.d);
            cur = Ray::new(origin, ray.d);
        }
        None
    }

    /// Asks the CPU to bring the mesh data of `hits` into the cache, before their surface
    /// points are computed one after the other: their cache misses then overlap.
    /// Does nothing for scenes whose meshes fit in the cache.
    pub fn prefetch_hits(&self, hits: &[Option<Hit>]) {
        if !self.large {
            return;
        }
        let meshes = || {
            hits.iter()
                .flatten()
                .filter_map(|h| match &self.shapes[h.shape as usize].kind {
                    ShapeKind::Mesh(m) => Some((m, h.prim as usize)),
                    _ => None,
                })
        };
        for (m, prim) in meshes() {
            m.prefetch_indices(prim);
        }
        for (m, prim) in meshes() {
            m.prefetch_vertices(prim);
        }
    }

    /// The surface point of `hit` found along `ray`, its shading normal tilted by its
    /// material's normal map or its shape's relief if it has one.
    pub fn interaction(&self, ray: &Ray, hit: &Hit) -> SurfaceInteraction {
        let shape = &self.shapes[hit.shape as usize];
        let mut si = SurfaceInteraction::from_hit(shape, ray, hit);
        if let (Material::MetallicRoughness(m), ShapeKind::Mesh(mesh)) =
            (&self.materials[shape.material], &shape.kind)
        {
            if let Some(map) = &m.normal_map {
                map.apply(&mut si, mesh);
            }
        }
        if let Some(relief) = &shape.relief {
            relief.apply(&mut si, shape);
        }
        si
    }

    /// Axis-aligned bounds of all geometry.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.bounds
    }

    /// A sphere enclosing all geometry (centre, radius), never of zero radius (a unit
    /// sphere when there is no geometry or a single point).
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        let (lo, hi) = self.bounds;
        let radius = fenestra_core::ray::robust_length(hi - lo) * 0.5;
        ((lo + hi) * 0.5, if radius > 0.0 { radius } else { 1.0 })
    }

    /// Triangles in all meshes.
    pub fn triangle_count(&self) -> usize {
        self.shapes
            .iter()
            .filter(|s| matches!(s.kind, ShapeKind::Mesh(_)))
            .map(Shape::primitive_count)
            .sum()
    }
}

fn validate(desc: &SceneDesc) -> Result<(), SceneError> {
    for (i, m) in desc.materials.iter().enumerate() {
        if let Some(what) = m.validate() {
            return Err(SceneError::Material { index: i, what });
        }
        // Components come first, so resolving a mix always ends.
        if let Material::Mix(material::Mix { materials, .. }) = m {
            if materials.iter().any(|&c| c >= i) {
                let what = format!("mix of materials {materials:?}: each must come before it");
                return Err(SceneError::Material { index: i, what });
            }
        }
    }
    for (i, s) in desc.shapes.iter().enumerate() {
        if s.material >= desc.materials.len() {
            return Err(SceneError::MaterialIndex {
                shape: i,
                material: s.material,
                count: desc.materials.len(),
            });
        }
        let geo = |what: String| Err(SceneError::Geometry { shape: i, what });
        if let Some(what) = crate::extent::extent_error(s.extent()) {
            return geo(what);
        }
        match &s.kind {
            ShapeKind::Mesh(m) => {
                for (t, tri) in m.indices.iter().enumerate() {
                    if let Some(&v) = tri.iter().find(|&&v| v as usize >= m.positions.len()) {
                        return Err(SceneError::VertexIndex {
                            shape: i,
                            triangle: t,
                            vertex: v,
                            count: m.positions.len(),
                        });
                    }
                }
                if m.positions.iter().any(|p| !p.is_finite()) {
                    return geo("a vertex position is not finite".into());
                }
                if m.normals
                    .as_ref()
                    .is_some_and(|n| n.len() != m.positions.len())
                {
                    return geo("normal count differs from vertex count".into());
                }
                if m.uvs.as_ref().is_some_and(|n| n.len() != m.positions.len()) {
                    return geo("uv count differs from vertex count".into());
                }
            }
            ShapeKind::Sphere { center, radius } => {
                if !(center.is_finite() && radius.is_finite() && *radius > 0.0) {
                    return geo(format!("sphere centre {center} radius {radius} invalid"));
                }
            }
            ShapeKind::Disk {
                center,
                normal,
                radius,
            } => {
                if !(center.is_finite() && radius.is_finite() && *radius > 0.0)
                    || (normal.length() - 1.0).abs() > 1e-3
                {
                    return geo(format!(
                        "disk centre {center} normal {normal} radius {radius} invalid"
                    ));
                }
            }
        }
        if let Some(e) = &s.emission {
            if !e.radiance.is_finite() || e.radiance.r.min(e.radiance.g).min(e.radiance.b) < 0.0 {
                return geo(format!("emitted radiance {:?} invalid", e.radiance));
            }
        }
    }
    for (i, l) in desc.lights.iter().enumerate() {
        if let Some(what) = l.problem() {
            return Err(SceneError::Light { index: i, what });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Material, TriangleMesh};

    #[test]
    fn geometry_lights_and_cameras_beyond_f32_are_refused() {
        let desc = |offset: f32| SceneDesc {
            name: "far".into(),
            shapes: vec![Shape::new(
                ShapeKind::Mesh(TriangleMesh::quad(Vec3::X * offset, Vec3::X, Vec3::Y)),
                0,
            )],
            materials: vec![Material::diffuse(0.5)],
            lights: vec![],
            camera: Camera::look_at(Vec3::new(0.0, -3.0, 1.0), Vec3::ZERO, Vec3::Z, 60.0)
                .expect("camera"),
            defaults: RenderDefaults::default(),
            portals: Vec::new(),
        };
        assert!(Scene::build(desc(1e11), Backend::Obvhs).is_ok());
        let e = Scene::build(desc(1e13), Backend::Obvhs)
            .err()
            .map(|e| e.to_string());
        assert!(
            e.as_deref()
                .is_some_and(|e| e.starts_with("shape 0: coordinates reach")),
            "{e:?}"
        );
        let mut d = desc(0.0);
        d.lights.push(LightDesc::Point {
            position: Vec3::Z * 2e12,
            intensity: fenestra_core::Rgb::ONE,
        });
        let e = Scene::build(d, Backend::Obvhs).err().map(|e| e.to_string());
        assert!(
            e.as_deref()
                .is_some_and(|e| e.starts_with("light 0: coordinates reach")),
            "{e:?}"
        );
        let far = Camera::look_at(Vec3::new(0.0, -3e38, 1.0), Vec3::ZERO, Vec3::Z, 60.0);
        assert!(matches!(far, Err(crate::CameraError::TooFar(_))), "{far:?}");
    }

    #[test]
    fn a_mix_must_name_earlier_materials_and_resolves_to_them() {
        let mix = |materials| {
            Material::Mix(material::Mix {
                materials,
                amount: 0.25,
            })
        };
        let desc = |materials: Vec<Material>| SceneDesc {
            name: "mix".into(),
            shapes: vec![Shape::new(
                ShapeKind::Mesh(TriangleMesh::quad(Vec3::ZERO, Vec3::X, Vec3::Y)),
                materials.len() - 1,
            )],
            materials,
            lights: vec![],
            camera: Camera::look_at(Vec3::new(0.0, -3.0, 1.0), Vec3::ZERO, Vec3::Z, 60.0)
                .expect("camera"),
            defaults: RenderDefaults::default(),
            portals: Vec::new(),
        };
        let looped = vec![Material::diffuse(0.5), mix([0, 1])];
        let e = Scene::build(desc(looped), Backend::Obvhs)
            .err()
            .map(|e| e.to_string());
        assert!(e.is_some_and(|e| e.contains("each must come before it")));
        // A mix of a mix: every point ends at material 0 or 1, about in the proportions
        // 0.75 * 0.75, 0.25 * 0.75 + 0.25 (the second mix picks its own second, material 1).
        let materials = vec![
            Material::diffuse(0.1),
            Material::diffuse(0.9),
            mix([0, 1]),
            mix([2, 1]),
        ];
        let n = 20_000;
        let ones = (0..n)
            .filter(|&i| {
                let p = Vec3::new(i as f32 * 0.37, (i % 97) as f32, 0.5);
                Material::resolve(&materials, 3, p) == 1
            })
            .count();
        let expect = 0.25 + 0.75 * 0.25;
        assert!(
            (ones as f64 / n as f64 - expect).abs() < 0.02,
            "{ones} of {n} points resolve to material 1, expected {expect}"
        );
        assert!(Scene::build(desc(materials), Backend::Obvhs).is_ok());
    }
}
