//! Pixel filters: a camera sample's film position is drawn from the scene's filter, so a
//! pixel beside a sharp edge sees the share of the filter that lies across it.

mod common;

use fenestra_core::{Rgb, Vec2, Vec3};
use fenestra_render::integrator::PathOptions;
use fenestra_render::{render_image, RenderScene, RenderSettings};
use fenestra_scene::filter::{FilterShape, PixelFilter};
use fenestra_scene::light::Emission;
use fenestra_scene::{
    Backend, Camera, Material, RenderDefaults, Scene, SceneDesc, Shape, ShapeKind, TriangleMesh,
};

/// Row 4 of a 16x8 image whose right half (from the film's centre line) sees an emitter of
/// radiance 1 and whose left half sees nothing, through `filter`.
fn edge_row(filter: PixelFilter) -> Vec<f32> {
    // World -x is the film's right: the emitter spans x in [-10, 0] in front of the camera.
    let emitter = TriangleMesh::quad(Vec3::new(-5.0, 0.0, 1.0), Vec3::X * 5.0, Vec3::Y * 10.0);
    let mut camera = Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0).expect("camera");
    camera.filter = filter;
    let desc = SceneDesc {
        name: "edge".into(),
        shapes: vec![Shape::new(ShapeKind::Mesh(emitter), 0).emitting(Emission {
            radiance: Rgb::ONE,
            two_sided: true,
        })],
        materials: vec![Material::diffuse(0.0)],
        lights: Vec::new(),
        camera,
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    };
    let scene = RenderScene::new(Scene::build(desc, Backend::Embree).expect("scene"));
    let mut integrator = common::integrator(
        "hf",
        PathOptions {
            max_depth: 1,
            ..Default::default()
        },
    );
    let settings = RenderSettings {
        first_sample: 0,
        spp: 1024,
        time_limit: None,
        seed: 1,
    };
    let (film, _) = render_image(integrator.as_mut(), &scene, 16, 8, &settings).expect("render");
    let image = film.image();
    (0..16).map(|x| image.get(x, 4).r).collect()
}

#[test]
fn a_pixel_beside_an_edge_sees_the_filter_across_it() {
    // The one-pixel box: the edge lies between pixels 7 and 8.
    let row = edge_row(PixelFilter::default());
    assert_eq!(&row[6..10], &[0.0, 0.0, 1.0, 1.0], "{row:?}");
    // A triangle of radius 2 centred on pixel 8's centre (0.5 right of the edge) leaves
    // 1/2 (1 - 0.5/2)^2 = 0.28125 of itself across the edge; pixel 9's leaves 0.03125.
    let row = edge_row(PixelFilter::new(FilterShape::Triangle, Vec2::splat(2.0)));
    for (x, expected) in [
        (5, 0.0),
        (6, 0.03125),
        (7, 0.28125),
        (8, 0.71875),
        (9, 0.96875),
        (10, 1.0),
    ] {
        assert!(
            (row[x] - expected).abs() < 0.01,
            "pixel {x}: {} against {expected} ({row:?})",
            row[x]
        );
    }
}
