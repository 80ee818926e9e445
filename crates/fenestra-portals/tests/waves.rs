//! Paths traced together in a wave (their rays eight to a packet query, their next-event
//! samples' shadow and probe rays traced after every path has taken its step) give each path
//! the estimate it gets alone, and the one the one-path loop gets with a query per ray: a
//! pixel does not depend on which other samples share its wave, so images stay the same for
//! any thread count, pass schedule or split of a render, and the packet queries (closest-hit,
//! any-hit, any-hit probes in sky-lit scenes) answer as the single ones do.

use fenestra_builtin as builtin;
use fenestra_core::{Rgb, Sampler, Vec3};
use fenestra_portals::estimate::EstimateParams;
use fenestra_portals::{lp_hf, PortalOptions, PortalSource};
use fenestra_render::driver::PathEstimator;
use fenestra_render::integrator::{af_hf, hf, LightNextEvent, PathOptions};
use fenestra_render::light::{LightRecords, LightSelection};
use fenestra_render::path_sample::{PathSample, Wave};
use fenestra_render::sample_context::SampleContext;
use fenestra_render::{Integrator, NoProgress, RayCounters, RenderControl, RenderScene};
use fenestra_scene::light::LightDesc;
use fenestra_scene::{mesh, Backend, Scene, SceneDesc, Shape, ShapeKind, TriangleMesh};
use std::sync::atomic::AtomicBool;

const SIZE: u32 = 16;

/// Every sample of a 16x16 image at 4 samples per pixel: in one wave, each alone in a wave
/// of its own, and each by the one-path loop (`li`, every ray its own query).
fn in_a_wave_and_alone(
    mut integrator: impl Integrator + PathEstimator,
    scene: &RenderScene,
) -> (Vec<Rgb>, Vec<Rgb>, Vec<Rgb>) {
    let cancel = AtomicBool::new(false);
    integrator
        .prepare(scene, &RenderControl::new(&cancel, &NoProgress))
        .expect("prepared");
    let ctxs: Vec<SampleContext> = (0..SIZE * SIZE * 4)
        .map(|i| SampleContext {
            x: (i / 4) % SIZE,
            y: (i / 4) / SIZE,
            width: SIZE,
            height: SIZE,
            block: 0,
            pass: 0,
            index: i % 4,
        })
        .collect();
    let fresh = || -> Vec<Sampler> {
        ctxs.iter()
            .map(|c| Sampler::new(7, c.pixel(), c.index))
            .collect()
    };
    let rays = &mut RayCounters::default();
    let mut samplers = fresh();
    let cameras: Vec<_> = ctxs
        .iter()
        .zip(&mut samplers)
        .map(|(c, s)| c.camera_ray(&scene.scene.camera, s, rays))
        .collect();
    let records = &mut LightRecords::off();
    let mut wave = vec![Rgb::ZERO; ctxs.len()];
    let mut streams = samplers.clone();
    let all = &mut Wave {
        cameras: &cameras,
        ctxs: &ctxs,
        samplers: &mut streams,
        records: &mut *records,
        rays: &mut *rays,
        features: &mut [],
    };
    integrator.li_many(scene, all, &mut wave);
    let mut alone = vec![Rgb::ZERO; ctxs.len()];
    for i in 0..ctxs.len() {
        let one = &mut Wave {
            cameras: &cameras[i..=i],
            ctxs: &ctxs[i..=i],
            samplers: &mut [samplers[i].clone()],
            records: &mut *records,
            rays: &mut *rays,
            features: &mut [],
        };
        integrator.li_many(scene, one, &mut alone[i..=i]);
    }
    let single: Vec<Rgb> = (0..ctxs.len())
        .map(|i| {
            let sample = &mut PathSample {
                ctx: &ctxs[i],
                sampler: &mut samplers[i].clone(),
                records: &mut *records,
                rays: &mut *rays,
            };
            integrator.li(scene, cameras[i], sample)
        })
        .collect();
    (wave, alone, single)
}

fn assert_same(label: &str, (wave, alone, single): (Vec<Rgb>, Vec<Rgb>, Vec<Rgb>)) {
    assert!(wave.iter().any(|l| !l.is_black()), "{label}: all black");
    for (i, ((a, b), c)) in wave.iter().zip(&alone).zip(&single).enumerate() {
        assert!(a == b, "{label}: sample {i} {a:?} in the wave, {b:?} alone");
        assert!(
            a == c,
            "{label}: sample {i} {a:?} in the wave, {c:?} by the one-path loop"
        );
    }
}

fn scene(name: &str, backend: Backend) -> RenderScene {
    scene_with(name, backend, |_| {})
}

/// [`scene`], changed by `change` first.
fn scene_with(name: &str, backend: Backend, change: impl FnOnce(&mut SceneDesc)) -> RenderScene {
    let mut desc = builtin::load(name).expect("builtin");
    change(&mut desc);
    // A point light besides the emitter: lp_hf then makes shadow rays (for it) as well as
    // probe rays (through the portal) at every vertex.
    desc.lights.push(LightDesc::Point {
        position: Vec3::new(0.3, -0.2, 0.1),
        intensity: Rgb::splat(0.05),
    });
    RenderScene::new(Scene::build(desc, backend).expect("scene"))
}

#[test]
fn a_path_in_a_wave_gets_the_estimate_it_gets_alone() {
    let path = PathOptions {
        max_depth: 6,
        ..PathOptions::default()
    };
    for backend in Backend::available() {
        let box_hole = scene("box-hole", backend);
        let name = |n: &str| format!("{n} ({})", backend.name());
        assert_same(&name("hf"), in_a_wave_and_alone(hf(path), &box_hole));
        let power = af_hf(path, LightSelection::Power);
        assert_same(&name("af_hf"), in_a_wave_and_alone(power, &box_hole));
        // Several shadow rays a vertex: one for each light.
        let all = af_hf(path, LightSelection::All);
        assert_same(&name("af_hf all"), in_a_wave_and_alone(all, &box_hole));
        let lights = LightNextEvent::new(LightSelection::Power);
        let portals = lp_hf(path, kept_portals(), PortalSource::Scene, lights).expect("lp_hf");
        assert_same(&name("lp_hf"), in_a_wave_and_alone(portals, &box_hole));
        // Only a sky beyond the portal: probes are any-hit queries in a wave (a slab under
        // the hole blocks some).
        let sky = scene_with("box-hole-sky", backend, |desc| {
            let slab = TriangleMesh::quad(Vec3::new(0.0, 0.0, 0.3), Vec3::X * 0.1, Vec3::Y * 0.1);
            desc.shapes.push(Shape::new(ShapeKind::Mesh(slab), 0));
        });
        assert!(!sky.has_surface_lights());
        let lights = LightNextEvent::new(LightSelection::Power);
        let portals = lp_hf(path, kept_portals(), PortalSource::Scene, lights).expect("lp_hf");
        assert_same(&name("lp_hf sky"), in_a_wave_and_alone(portals, &sky));
        // A mesh larger than the cache: a packet's hits are prefetched before its paths step.
        let dense = scene_with("box-hole", backend, |desc| {
            let floor = mesh::grid(256, 256, false, |s, t| Vec3::new(s - 0.5, t - 0.5, -0.45));
            assert!(
                floor.bytes() > 1 << 20,
                "beyond the prefetch threshold (1 MiB)"
            );
            desc.shapes.push(Shape::new(ShapeKind::Mesh(floor), 0));
        });
        let power = af_hf(path, LightSelection::Power);
        assert_same(&name("af_hf dense"), in_a_wave_and_alone(power, &dense));
        // Thin glass: rays follow panes one query at a time (portals estimated).
        let hall = scene("hall-windows", backend);
        let lights = LightNextEvent::new(LightSelection::Power);
        // Untimed: the photons then depend on nothing but the parameters.
        let mut params = EstimateParams::default();
        params.photons.time_limit = None;
        let estimated = PortalSource::Estimated {
            params,
            cache: None,
        };
        let portals = lp_hf(path, kept_portals(), estimated, lights).expect("lp_hf");
        assert_same(&name("lp_hf hall"), in_a_wave_and_alone(portals, &hall));
    }
}

/// Default portal options, the portals kept whatever lp_hf's measurement before rendering
/// finds (these tests are about sampling them).
fn kept_portals() -> PortalOptions {
    PortalOptions {
        keep: true,
        ..PortalOptions::default()
    }
}
