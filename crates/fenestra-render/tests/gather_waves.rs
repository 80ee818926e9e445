//! A cache of indirect light (a [`Gather`]) on paths traced together in a wave: it is asked at
//! the camera's hits in the order the one-path loop asks it there, and the paths get the
//! estimates they get one at a time. sdrc's caches grow as they are asked (records, samples),
//! so that order is what keeps its waves' pixels those of one path at a time.

use fenestra_core::stats::RayCounters;
use fenestra_core::{Rgb, Sampler};
use fenestra_render::integrator::{
    Gather, LightNextEvent, PathOptions, PathTracer, Shading, Start,
};
use fenestra_render::light::{LightRecords, LightSelection};
use fenestra_render::path_sample::{PathSample, Wave};
use fenestra_render::sample_context::SampleContext;
use fenestra_render::RenderScene;
use fenestra_scene::{Backend, Scene};

const SIZE: u32 = 16;

/// Answers at the camera's hits with light that grows with every answer (as a cache that
/// learns from its queries would), and lets other vertices' paths go on; it remembers the
/// pixels it was asked for, in order.
#[derive(Default)]
struct Counting {
    asked: Vec<(u32, u32)>,
}

impl Gather for Counting {
    fn indirect(
        &mut self,
        _: &RenderScene,
        s: &Shading,
        segments: u32,
        _: &mut RayCounters,
    ) -> Option<Rgb> {
        if segments != 1 {
            return None;
        }
        self.asked.push((s.sample.x, s.sample.y));
        Some(Rgb::splat(1e-3 * self.asked.len() as f32))
    }
}

#[test]
fn a_cache_on_waves_is_asked_in_the_order_and_gives_the_pixels_of_one_path_at_a_time() {
    let desc = fenestra_builtin::load("teapot-box").expect("built-in scene");
    for backend in Backend::available() {
        let scene = RenderScene::new(Scene::build(desc.clone(), backend).expect("scene"));
        let path = PathOptions {
            max_depth: 5,
            ..PathOptions::default()
        };
        let tracer = PathTracer::new("test", LightNextEvent::new(LightSelection::Power), path);
        let ctxs: Vec<SampleContext> = (0..SIZE * SIZE * 2)
            .map(|i| SampleContext {
                x: (i / 2) % SIZE,
                y: (i / 2) / SIZE,
                width: SIZE,
                height: SIZE,
                block: 0,
                pass: 0,
                index: i % 2,
            })
            .collect();
        let rays = &mut RayCounters::default();
        let mut samplers: Vec<Sampler> = ctxs
            .iter()
            .map(|c| Sampler::new(11, c.pixel(), c.index))
            .collect();
        let cameras = SampleContext::camera_rays(&ctxs, &scene.scene.camera, &mut samplers, rays);
        let records = &mut LightRecords::off();

        let mut one_at_a_time = Counting::default();
        let alone: Vec<Rgb> = (0..ctxs.len())
            .map(|i| {
                let sample = &mut PathSample {
                    ctx: &ctxs[i],
                    sampler: &mut samplers[i].clone(),
                    records: &mut *records,
                    rays: &mut *rays,
                };
                tracer.trace(
                    &scene,
                    cameras[i],
                    Start::CAMERA,
                    sample,
                    &mut one_at_a_time,
                )
            })
            .collect();
        let mut in_waves = Counting::default();
        let mut wave = vec![Rgb::ZERO; ctxs.len()];
        let all = &mut Wave {
            cameras: &cameras,
            ctxs: &ctxs,
            samplers: &mut samplers,
            records,
            rays,
            features: &mut [],
        };
        tracer.trace_wave(&scene, all, &mut in_waves, &mut wave);

        let label = backend.name();
        assert!(
            one_at_a_time.asked.len() > ctxs.len() / 2,
            "{label}: few hits"
        );
        assert!(
            in_waves.asked == one_at_a_time.asked,
            "{label}: asked in another order"
        );
        for (i, (a, b)) in wave.iter().zip(&alone).enumerate() {
            assert!(a == b, "{label}: sample {i} {a:?} in the wave, {b:?} alone");
        }
    }
}
