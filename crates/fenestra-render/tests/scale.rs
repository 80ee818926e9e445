//! Geometry is scale-invariant: a scene in micrometres, millimetres, kilometres or
//! gigametres, up to the 1e12 m from the origin that f32 resolves (1e11 times a 3 m box),
//! renders the image it renders in metres (ray offsets and intersection tests are relative to
//! the magnitudes involved), with both ray-query backends; and sphere lights of any radius
//! down to a micrometre converge to the point light of the same power.

mod common;

use fenestra_builtin as builtin;
use fenestra_core::{Rgb, Vec3};
use fenestra_render::integrator::PathOptions;
use fenestra_render::{render_image, Film, RenderScene, RenderSettings};
use fenestra_scene::light::Emission;
use fenestra_scene::{
    Backend, Camera, LightDesc, Material, RenderDefaults, Scene, SceneDesc, Shape, ShapeKind,
    TriangleMesh,
};

fn render(desc: SceneDesc, backend: Backend, name: &str, depth: u32, spp: u32, seed: u64) -> Film {
    let scene = RenderScene::new(Scene::build(desc, backend).expect("scene"));
    let options = PathOptions {
        max_depth: depth,
        ..Default::default()
    };
    let settings = RenderSettings {
        first_sample: 0,
        spp,
        time_limit: None,
        seed,
    };
    let mut integrator = common::integrator(name, options);
    render_image(integrator.as_mut(), &scene, 24, 24, &settings)
        .expect("render")
        .0
}

#[test]
fn a_scene_renders_the_same_at_every_scale() {
    let backends = [Backend::Embree, Backend::Obvhs];
    for (scene, name, depth, spp) in [
        ("box-hole", "af_hf", 4, 128),
        ("box-hole", "hf", 3, 1024),
        ("teapot-box", "af_hf", 3, 64),
    ] {
        let load = || builtin::load(scene).expect("builtin");
        let metres = render(load(), Backend::Embree, name, depth, spp, 1);
        for backend in backends {
            for s in [1e-6f32, 1e-3, 1e3, 1e6, 1e9, 1e11] {
                let scaled = render(load().scaled(s), backend, name, depth, spp, 2);
                common::assert_agree(
                    &format!("{scene} {name} scaled by {s:e} ({backend:?})"),
                    &metres,
                    &scaled,
                );
            }
        }
    }
}

/// A 4 m grey floor seen from 3 m above, lit by `light` 1 m above its centre.
fn floor_with(lights: Vec<LightDesc>, sphere: Option<Shape>) -> SceneDesc {
    let floor = TriangleMesh::quad(Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 2.0);
    let mut shapes = vec![Shape::new(ShapeKind::Mesh(floor), 0)];
    shapes.extend(sphere);
    SceneDesc {
        name: "floor".into(),
        shapes,
        materials: vec![Material::diffuse(0.5)],
        lights,
        camera: Camera::look_at(Vec3::new(0.0, -0.5, 3.0), Vec3::ZERO, Vec3::Y, 60.0)
            .expect("camera"),
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    }
}

#[test]
fn sphere_lights_converge_to_the_point_light_of_their_power() {
    let power = 100.0f32;
    let at = Vec3::new(0.3, 0.2, 1.0);
    let point = floor_with(
        vec![LightDesc::Point {
            position: at,
            intensity: Rgb::splat(power / (4.0 * std::f32::consts::PI)),
        }],
        None,
    );
    // Direct light only: the point light's image has only the pixel footprint's variance.
    let reference = render(point, Backend::Embree, "af_hf", 2, 64, 1);
    let (mean, _) = common::region_mean(&reference, 0, 24, 0, 24);
    for radius in [1e-3f32, 1e-4, 1e-5, 1e-6] {
        let area = 4.0 * std::f32::consts::PI * radius * radius;
        let sphere = Shape::new(ShapeKind::Sphere { center: at, radius }, 0)
            .emitting(Emission::from_power(Rgb::splat(power), area, false));
        let film = render(
            floor_with(vec![], Some(sphere)),
            Backend::Embree,
            "af_hf",
            2,
            64,
            2,
        );
        let (m, _) = common::region_mean(&film, 0, 24, 0, 24);
        assert!(
            (m / mean - 1.0).abs() < 0.01,
            "radius {radius}: mean {m} against the point light's {mean}"
        );
        common::assert_agree(&format!("sphere of radius {radius}"), &reference, &film);
    }
}
