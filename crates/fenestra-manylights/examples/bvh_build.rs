//! Builds the light BVH over N emissive triangles scattered in a 100 m cube (default 100,000)
//! and prints the build time and the memory per light.
//!
//! cargo run --release -p fenestra-manylights --example bvh_build -- [N]

use fenestra_core::{warp, Rgb, Rng, Vec3};
use fenestra_manylights::LightBvh;
use fenestra_render::light::Lights;
use fenestra_scene::light::Emission;
use fenestra_scene::{
    Backend, Camera, Material, RenderDefaults, Scene, SceneDesc, Shape, ShapeKind, TriangleMesh,
};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args().nth(1).map_or(Ok(100_000), |a| a.parse())?;
    let mut rng = Rng::new(1);
    let mut mesh = TriangleMesh::default();
    for t in 0..n {
        let c = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 100.0;
        let (a, b) = (
            warp::square_to_uniform_sphere(rng.next_2d()) * 0.2,
            warp::square_to_uniform_sphere(rng.next_2d()) * 0.2,
        );
        mesh.positions.extend([c, c + a, c + b]);
        let k = 3 * t as u32;
        mesh.indices.push([k, k + 1, k + 2]);
    }
    let desc = SceneDesc {
        name: "triangles".into(),
        shapes: vec![Shape::new(ShapeKind::Mesh(mesh), 0).emitting(Emission::radiance(Rgb::ONE))],
        materials: vec![Material::diffuse(0.5)],
        lights: vec![],
        camera: Camera::look_at(Vec3::splat(-10.0), Vec3::ZERO, Vec3::Z, 60.0)?,
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    };
    let scene = Scene::build(desc, Backend::Obvhs)?;
    let lights = Lights::new(&scene);
    let start = Instant::now();
    let bvh = LightBvh::new(&scene, &lights);
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "{} lights: light BVH built in {seconds:.3} s, {:.0} bytes per light",
        lights.lights.len(),
        bvh.bytes_per_light()
    );
    Ok(())
}
