//! Normal maps tilt the shading normal the way the map says, towards +u for red and +v for
//! green, and touch nothing else of a hit; a flat map changes nothing, bit for bit.

use fenestra_core::image::Image;
use fenestra_core::{Ray, Rgb, Vec3};
use fenestra_scene::material::{MetallicRoughness, NormalMap};
use fenestra_scene::{
    Backend, Camera, ImageTexture, Material, RenderDefaults, Scene, SceneDesc, Shape, ShapeKind,
    SurfaceInteraction, TriangleMesh,
};
use std::sync::Arc;

/// A quad in the z = 0 plane (u along +x, v along +y, facing +z) whose material has a normal
/// map of one texel `texel`, or none.
fn plate(texel: Option<Rgb>) -> Scene {
    let normal_map = texel.map(|c| {
        let mut img = Image::new(1, 1);
        img.set(0, 0, c);
        NormalMap {
            texture: Arc::new(ImageTexture::new(Arc::new(img), "n.png".into())),
            scale: 1.0,
        }
    });
    let desc = SceneDesc {
        name: "plate".into(),
        shapes: vec![Shape::new(
            ShapeKind::Mesh(TriangleMesh::quad(Vec3::ZERO, Vec3::X, Vec3::Y)),
            0,
        )],
        materials: vec![Material::MetallicRoughness(MetallicRoughness {
            normal_map,
            ..MetallicRoughness::new()
        })],
        lights: vec![],
        camera: Camera::look_at(Vec3::Z * 3.0, Vec3::ZERO, Vec3::Y, 60.0).expect("camera"),
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    };
    Scene::build(desc, Backend::Obvhs).expect("scene")
}

fn hit(scene: &Scene) -> SurfaceInteraction {
    let ray = Ray::new(
        Vec3::new(0.3, -0.2, 2.0),
        Vec3::new(0.05, 0.1, -1.0).normalize(),
    );
    let h = scene.intersect(&ray, f32::INFINITY).expect("hit");
    scene.interaction(&ray, &h)
}

#[test]
fn a_flat_normal_map_changes_nothing() {
    let (plain, flat) = (
        hit(&plate(None)),
        hit(&plate(Some(Rgb::new(0.5, 0.5, 1.0)))),
    );
    assert_eq!(format!("{plain:?}"), format!("{flat:?}"));
}

#[test]
fn red_tilts_towards_u_and_green_towards_v_and_nothing_else_moves() {
    let plain = hit(&plate(None));
    for (texel, expect) in [
        (Rgb::new(0.75, 0.5, 1.0), Vec3::new(0.5, 0.0, 1.0)),
        (Rgb::new(0.5, 0.75, 1.0), Vec3::new(0.0, 0.5, 1.0)),
        (Rgb::new(0.5, 0.25, 1.0), Vec3::new(0.0, -0.5, 1.0)),
    ] {
        let si = hit(&plate(Some(texel)));
        assert!(
            (si.ns - expect.normalize()).length() < 1e-5,
            "{texel:?}: {}",
            si.ns
        );
        assert_eq!(
            (si.p, si.ng, si.t, si.uv),
            (plain.p, plain.ng, plain.t, plain.uv)
        );
    }
    // A map pointing below the surface is held just above it.
    let si = hit(&plate(Some(Rgb::new(1.0, 0.5, 0.0))));
    assert!(
        si.ns.dot(si.ng) > 0.0 && si.ns.dot(si.ng) < 0.05,
        "{}",
        si.ns
    );
}
