//! Scenes shared by the integration tests.
#![allow(dead_code)] // each test binary uses a part

use fenestra_core::{warp, Rgb, Rng, Vec3};
use fenestra_manylights::LightBvh;
use fenestra_render::integrator::{LightNextEvent, PathOptions, PathTracer};
use fenestra_render::{render_image, Film, Integrator, RenderScene, RenderSettings};
use fenestra_scene::light::{Emission, EnvironmentDesc};
use fenestra_scene::{
    Backend, Camera, LightDesc, Material, RenderDefaults, Scene, SceneDesc, Shape, ShapeKind,
    TriangleMesh,
};

/// Forty-odd lights of every kind in a room: point and spot lights, one- and two-sided
/// emitting quads (two triangles each), spheres and disks, and a sky.
pub fn many_lights() -> SceneDesc {
    let mut rng = Rng::new(17);
    let mut shapes = vec![Shape::new(
        ShapeKind::Mesh(TriangleMesh::quad(Vec3::ZERO, Vec3::X * 4.0, Vec3::Y * 4.0)),
        0,
    )];
    let mut lights = vec![LightDesc::Environment(EnvironmentDesc::Constant(
        Rgb::splat(0.05),
    ))];
    let at = |rng: &mut Rng| {
        Vec3::new(
            8.0 * rng.next_f32() - 4.0,
            8.0 * rng.next_f32() - 4.0,
            0.5 + 2.5 * rng.next_f32(),
        )
    };
    for k in 0..8 {
        let p = at(&mut rng);
        lights.push(LightDesc::Point {
            position: p,
            intensity: Rgb::splat(0.5 + k as f32),
        });
        let p = at(&mut rng);
        lights.push(LightDesc::Spot {
            position: p,
            direction: warp::square_to_uniform_sphere(rng.next_2d()),
            intensity: Rgb::splat(2.0),
            cone_angle: 40.0,
            falloff_start: 25.0,
        });
        let c = at(&mut rng);
        let quad = TriangleMesh::quad(
            c,
            warp::square_to_uniform_sphere(rng.next_2d()) * 0.3,
            warp::square_to_uniform_sphere(rng.next_2d()) * 0.2,
        );
        let emission = Emission {
            radiance: Rgb::splat(1.0 + k as f32),
            two_sided: k % 2 == 0,
        };
        shapes.push(Shape::new(ShapeKind::Mesh(quad), 0).emitting(emission));
        shapes.push(
            Shape::new(
                ShapeKind::Sphere {
                    center: at(&mut rng),
                    radius: 0.1,
                },
                0,
            )
            .emitting(Emission::radiance(Rgb::splat(3.0))),
        );
        shapes.push(
            Shape::new(
                ShapeKind::Disk {
                    center: at(&mut rng),
                    normal: warp::square_to_uniform_sphere(rng.next_2d()),
                    radius: 0.15,
                },
                0,
            )
            .emitting(Emission::radiance(Rgb::splat(2.0))),
        );
    }
    SceneDesc {
        name: "many lights".into(),
        shapes,
        materials: vec![Material::diffuse(0.6)],
        lights,
        camera: Camera::look_at(Vec3::new(0.0, -6.0, 4.0), Vec3::ZERO, Vec3::Z, 60.0)
            .expect("camera"),
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    }
}

/// af_hf with the light BVH.
pub fn bvh_af_hf(options: PathOptions) -> PathTracer<LightNextEvent> {
    PathTracer::new(
        "af_hf",
        LightNextEvent::with_sampler("bvh", |s: &RenderScene| {
            Box::new(LightBvh::new(&s.scene, &s.lights))
        }),
        options,
    )
}

/// Renders `desc` at 24x24 with `spp` samples on `threads` threads.
pub fn render(desc: SceneDesc, integrator: &mut dyn Integrator, spp: u32, threads: usize) -> Film {
    let scene = RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"));
    let settings = RenderSettings {
        first_sample: 0,
        spp,
        time_limit: None,
        seed: 5,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    pool.install(|| render_image(integrator, &scene, 24, 24, &settings))
        .expect("render")
        .0
}
