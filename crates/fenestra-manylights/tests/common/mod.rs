//! Scenes shared by the integration tests.
#![allow(dead_code)] // each test binary uses a part

use fenestra_core::{warp, Rgb, Rng, Vec3};
use fenestra_manylights::LightBvh;
use fenestra_render::integrator::{LightNextEvent, PathOptions, PathTracer};
use fenestra_render::light::{LightContext, LightSampler};
use fenestra_render::sample_context::SampleContext;
use fenestra_render::{render_image, Film, Integrator, RenderScene, RenderSettings};
use fenestra_scene::light::{Emission, EnvironmentDesc};
use fenestra_scene::material;
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

/// The forty-light room with a polished floor (Phong, exponent 300), a brighter sky, a glass
/// ball on the floor and a tiled emitting panel standing on it: narrow lobes, a mirror-like
/// surface and points near a light, where light samples alone do poorly.
pub fn glossy_many_lights() -> SceneDesc {
    let mut desc = many_lights();
    desc.name = "glossy many lights".into();
    desc.materials[0] = Material::Phong(material::Phong {
        diffuse: Rgb::splat(0.2),
        specular: Rgb::splat(0.5),
        exponent: 300.0,
    });
    desc.materials
        .push(Material::Dielectric(material::Dielectric { eta: 1.5 }));
    // A brighter sky, which the floor mirrors.
    desc.lights[0] = LightDesc::Environment(EnvironmentDesc::Constant(Rgb::splat(0.4)));
    desc.shapes.push(Shape::new(
        ShapeKind::Sphere {
            center: Vec3::new(-0.8, 0.5, 0.5),
            radius: 0.5,
        },
        1,
    ));
    // The panel as 8 x 6 tiles (96 lights), so that far from it its lights form clusters.
    for i in 0..8 {
        for k in 0..6 {
            let c = Vec3::new(1.0 + 0.125 * i as f32, 2.5, 0.1 + 0.125 * k as f32);
            let tile = TriangleMesh::quad(c, Vec3::X * 0.0625, Vec3::Z * 0.0625);
            let glow = Emission::radiance(Rgb::splat(2.0));
            desc.shapes
                .push(Shape::new(ShapeKind::Mesh(tile), 0).emitting(glow));
        }
    }
    desc
}

/// A polished floor (Phong, exponent 300) and a wall meeting it, lit by a panel that stands
/// on the floor against the wall and by 25 dim point lights 2 m up; seen from where the
/// floor mirrors the panel. Light samples alone do poorly at both: the floor's lobe is
/// narrow, and the wall's points beside the panel see it across a wide angle.
pub fn polished_floor_by_a_panel() -> SceneDesc {
    let mut lights = Vec::new();
    for i in 0..5 {
        for j in 0..5 {
            lights.push(LightDesc::Point {
                position: Vec3::new(i as f32 - 2.0, j as f32 - 2.0, 2.0),
                intensity: Rgb::splat(0.05),
            });
        }
    }
    let floor = TriangleMesh::quad(Vec3::new(0.0, 0.0, 0.0), Vec3::X * 3.0, Vec3::Y * 3.0);
    let wall = TriangleMesh::quad(Vec3::new(0.0, 1.5, 1.0), Vec3::X * 3.0, Vec3::Z * 1.0);
    let panel = TriangleMesh::quad(Vec3::new(0.0, 1.45, 0.4), Vec3::X * 0.6, Vec3::Z * 0.4);
    SceneDesc {
        name: "polished floor by a panel".into(),
        shapes: vec![
            Shape::new(ShapeKind::Mesh(floor), 0),
            Shape::new(ShapeKind::Mesh(wall), 1),
            Shape::new(ShapeKind::Mesh(panel), 1).emitting(Emission::radiance(Rgb::splat(3.0))),
        ],
        materials: vec![
            Material::Phong(material::Phong {
                diffuse: Rgb::splat(0.1),
                specular: Rgb::splat(0.6),
                exponent: 300.0,
            }),
            Material::diffuse(0.7),
        ],
        lights,
        camera: Camera::look_at(
            Vec3::new(0.0, -1.5, 0.8),
            Vec3::new(0.0, 1.0, 0.2),
            Vec3::Z,
            60.0,
        )
        .expect("camera"),
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    }
}

/// A floor lit by one bright point light 0.3 above it and 169 dim ones on a grid 2 m up,
/// seen from above where the bright light gives nearly all the light: most of the dim lights
/// are clusters of their own, so a pass uniform over the clusters often misses the bright one.
pub fn one_bright_among_many() -> SceneDesc {
    let mut lights = vec![LightDesc::Point {
        position: Vec3::new(0.0, 0.0, 0.3),
        intensity: Rgb::splat(2.0),
    }];
    for i in 0..13 {
        for j in 0..13 {
            lights.push(LightDesc::Point {
                position: Vec3::new(i as f32 * 0.67 - 4.0, j as f32 * 0.67 - 4.0, 2.0),
                intensity: Rgb::splat(0.02),
            });
        }
    }
    SceneDesc {
        name: "one bright among many".into(),
        shapes: vec![Shape::new(
            ShapeKind::Mesh(TriangleMesh::quad(Vec3::ZERO, Vec3::X * 4.0, Vec3::Y * 4.0)),
            0,
        )],
        materials: vec![Material::diffuse(0.6)],
        lights,
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 20.0)
            .expect("camera"),
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    }
}

/// A closed 8 x 8 x 3 m room under 64 ceiling panels of unequal power, with six boxes of
/// several heights on the floor that hide many panels from much of it; the camera looks
/// down at the floor and the boxes and sees no light.
pub fn occluded_room() -> SceneDesc {
    let mut rng = Rng::new(64);
    let mut shapes = room_with_boxes(None);
    for i in 0..8 {
        for j in 0..8 {
            let c = Vec3::new(0.5 + i as f32, 0.5 + j as f32, 2.99);
            let panel = TriangleMesh::quad(c, Vec3::Y * 0.15, Vec3::X * 0.15);
            let e = 2.0 + 18.0 * rng.next_f32();
            let glow = Emission::radiance(Rgb::new(e, 0.9 * e, 0.8 * e));
            shapes.push(Shape::new(ShapeKind::Mesh(panel), 0).emitting(glow));
        }
    }
    room_seen_from_its_corner("occluded room", shapes, Vec::new())
}

/// [`occluded_room`]'s room and boxes with no lamp, lit by a sky (and its sun, with `sun`)
/// through the opening `[x0, y0], [x1, y1]` in the ceiling: each part of the floor and the
/// boxes sees its own part of the sky (or none).
pub fn skylit_room(opening: ([f32; 2], [f32; 2]), sun: bool) -> SceneDesc {
    let shapes = room_with_boxes(Some(opening));
    let sky = fenestra_scene::sky::Sky {
        turbidity: 3.0,
        albedo: 0.3,
        elevation_deg: 60.0,
        azimuth_deg: 250.0,
    };
    let mut desc = room_seen_from_its_corner("skylit room", shapes, Vec::new())
        .with_sky(&sky, Vec3::Z, 0.0, 1.0)
        .expect("a valid sky");
    if !sun {
        desc.lights
            .retain(|l| !matches!(l, LightDesc::Environment(EnvironmentDesc::Sun { .. })));
    }
    desc
}

/// The floor, walls and ceiling of an 8 x 8 x 3 m room, the ceiling with an opening
/// `[x0, y0], [x1, y1]` if given, and six boxes of several heights on the floor.
fn room_with_boxes(opening: Option<([f32; 2], [f32; 2])>) -> Vec<Shape> {
    let mut inward = vec![
        (Vec3::new(4.0, 4.0, 0.0), Vec3::X * 4.0, Vec3::Y * 4.0),
        (Vec3::new(4.0, 0.0, 1.5), Vec3::Z * 1.5, Vec3::X * 4.0),
        (Vec3::new(4.0, 8.0, 1.5), Vec3::X * 4.0, Vec3::Z * 1.5),
        (Vec3::new(0.0, 4.0, 1.5), Vec3::Y * 4.0, Vec3::Z * 1.5),
        (Vec3::new(8.0, 4.0, 1.5), Vec3::Z * 1.5, Vec3::Y * 4.0),
    ];
    // The ceiling, facing down: whole, or as the four rectangles around the opening.
    let ceiling = |[x0, y0]: [f32; 2], [x1, y1]: [f32; 2]| {
        let c = Vec3::new(0.5 * (x0 + x1), 0.5 * (y0 + y1), 3.0);
        (c, Vec3::Y * (0.5 * (y1 - y0)), Vec3::X * (0.5 * (x1 - x0)))
    };
    match opening {
        None => inward.push(ceiling([0.0, 0.0], [8.0, 8.0])),
        Some(([x0, y0], [x1, y1])) => inward.extend([
            ceiling([0.0, 0.0], [x0, 8.0]),
            ceiling([x1, 0.0], [8.0, 8.0]),
            ceiling([x0, 0.0], [x1, y0]),
            ceiling([x0, y1], [x1, 8.0]),
        ]),
    }
    let mut shapes: Vec<Shape> = inward
        .iter()
        .map(|&(c, u, v)| Shape::new(ShapeKind::Mesh(TriangleMesh::quad(c, u, v)), 0))
        .collect();
    for (x, y, height) in [
        (1.5, 2.0, 2.2),
        (4.0, 2.5, 1.2),
        (6.5, 2.0, 2.5),
        (2.0, 5.5, 1.8),
        (4.5, 6.0, 2.6),
        (6.5, 5.5, 1.0),
    ] {
        let h = Vec3::new(0.6, 0.6, height / 2.0);
        let c = Vec3::new(x, y, height / 2.0);
        let (hx, hy, hz) = (Vec3::X * h.x, Vec3::Y * h.y, Vec3::Z * h.z);
        for (centre, u, v) in [
            (c + hx, hy, hz),
            (c - hx, hz, hy),
            (c + hy, hz, hx),
            (c - hy, hx, hz),
            (c + hz, hx, hy),
        ] {
            shapes.push(Shape::new(
                ShapeKind::Mesh(TriangleMesh::quad(centre, u, v)),
                0,
            ));
        }
    }
    shapes
}

/// A scene of `shapes` (one diffuse material) and `lights`, seen from near a corner of
/// [`room_with_boxes`]'s room, looking down at the floor and the boxes.
fn room_seen_from_its_corner(name: &str, shapes: Vec<Shape>, lights: Vec<LightDesc>) -> SceneDesc {
    SceneDesc {
        name: name.into(),
        shapes,
        materials: vec![Material::diffuse(0.7)],
        lights,
        camera: Camera::look_at(
            Vec3::new(4.0, 0.3, 2.6),
            Vec3::new(4.0, 4.5, 0.0),
            Vec3::Z,
            70.0,
        )
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
    render_with(desc, integrator, (24, 24), spp, 5, threads)
}

/// Renders `desc` at `width` x `height` with `spp` samples and `seed` on `threads` threads.
pub fn render_with(
    desc: SceneDesc,
    integrator: &mut dyn Integrator,
    (width, height): (u32, u32),
    spp: u32,
    seed: u64,
    threads: usize,
) -> Film {
    let scene = RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"));
    let settings = RenderSettings {
        first_sample: 0,
        spp,
        time_limit: None,
        seed,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    pool.install(|| render_image(integrator, &scene, width, height, &settings))
        .expect("render")
        .0
}

/// Checks a light sampler at `ctx` over `count` lights: its probabilities sum to at most one
/// (a descent may pick nothing where nothing can reach), each pick reports the probability
/// `pmf` gives, and 200,000 picks follow the probabilities (chi-square at level `alpha`, the
/// share of no pick as one more bin).
pub fn picks_follow_pmf(
    sampler: &dyn LightSampler,
    ctx: &LightContext,
    count: usize,
    rng: &mut Rng,
    alpha: f64,
) {
    let p = ctx.p;
    let pmf: Vec<f64> = (0..count).map(|i| f64::from(sampler.pmf(ctx, i))).collect();
    let total: f64 = pmf.iter().sum();
    assert!(
        total <= 1.0 + 1e-4 && total > 0.5,
        "at {p}: probabilities sum to {total}"
    );
    const DRAWS: usize = 200_000;
    let mut counts = vec![0.0f64; pmf.len() + 1];
    for _ in 0..DRAWS {
        let Some((i, q)) = sampler.sample(ctx, rng.next_f32()) else {
            counts[pmf.len()] += 1.0;
            continue;
        };
        assert!(
            (f64::from(q) - pmf[i]).abs() <= 1e-4 * pmf[i].max(1e-3),
            "sampled probability {q} of light {i} vs pmf {}",
            pmf[i]
        );
        counts[i] += 1.0;
    }
    let expected: Vec<f64> = pmf
        .iter()
        .copied()
        .chain([(1.0 - total).max(0.0)])
        .collect();
    let p_value = chi_square(&counts, &expected);
    assert!(p_value > alpha, "at {p}: p = {p_value:.2e}");
}

/// The p-value of `counts` drawn from the probabilities `expected` (the shared chi-square
/// harness); panics if a bin of zero probability has counts.
pub fn chi_square(counts: &[f64], expected: &[f64]) -> f64 {
    let draws: f64 = counts.iter().sum();
    let expected: Vec<f64> = expected.iter().map(|p| p * draws).collect();
    let fit = fenestra_eval::chi2::chi2(counts, &expected, 0.0)
        .unwrap_or_else(|e| panic!("something of zero probability was picked: {e}"));
    eprintln!(
        "chi2 {:.1}, {} dof, p = {:.3}",
        fit.statistic, fit.dof, fit.p_value
    );
    fit.p_value
}

/// The sample light samplers see in tests of single points.
pub const SAMPLE: SampleContext = SampleContext::SINGLE;

/// Six points in [many_lights]'s room with random normals; the first receives from every
/// side (a zero normal).
pub fn test_points(rng: &mut Rng) -> Vec<(Vec3, Vec3)> {
    (0..6)
        .map(|k| {
            let p = Vec3::new(
                6.0 * rng.next_f32() - 3.0,
                6.0 * rng.next_f32() - 3.0,
                3.0 * rng.next_f32(),
            );
            let n = if k == 0 {
                Vec3::ZERO
            } else {
                warp::square_to_uniform_sphere(rng.next_2d())
            };
            (p, n)
        })
        .collect()
}

/// af_hf with the light sampler `make` gives agrees with power selection (z-tests over the
/// image and 8x8 regions, 256 samples, path length 3) on the 40-light scene and
/// kitchen-72-env, with the same pixels on one thread as on two; returns each scene's name
/// and its 16-sample image.
pub fn agrees_with_power_selection(
    make: impl Fn(PathOptions) -> PathTracer<LightNextEvent>,
) -> Vec<(&'static str, Film)> {
    let options = PathOptions {
        max_depth: 3,
        ..Default::default()
    };
    ["many lights", "kitchen-72-env"]
        .into_iter()
        .map(|name| {
            let scene = || match name {
                "many lights" => many_lights(),
                other => fenestra_builtin::load(other).expect("builtin"),
            };
            let mut power = fenestra_render::integrator::af_hf(
                options,
                fenestra_render::light::LightSelection::Power,
            );
            let power = render(scene(), &mut power, 256, 2);
            let image = render(scene(), &mut make(options), 256, 2);
            let t = fenestra_eval::agreement(&power.estimate(), &image.estimate(), 0.01, 8)
                .expect("sizes");
            assert!(t.passed(), "{name}: {t:?}");
            let one = render(scene(), &mut make(options), 16, 1);
            let two = render(scene(), &mut make(options), 16, 2);
            assert_eq!(
                one.estimate().mean.pixels,
                two.estimate().mean.pixels,
                "{name}: 1 and 2 threads"
            );
            (name, one)
        })
        .collect()
}
