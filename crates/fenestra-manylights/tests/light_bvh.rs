//! The light BVH as a light sampler: its probabilities sum to one, its picks follow them
//! (chi-square), it reports the probability of what it picks, and af_hf renders the same
//! image with it as with power selection, the same with one thread as with two; so does a
//! tree that splits, whose picks come as often as its probabilities say.

mod common;

use common::{
    agrees_with_power_selection, bvh_af_hf, many_lights, picks_follow_pmf, test_points, SAMPLE,
};
use fenestra_core::Rng;
use fenestra_manylights::LightBvh;
use fenestra_render::integrator::{LightNextEvent, PathTracer};
use fenestra_render::light::{LightContext, LightSampler, Lights, Picks};
use fenestra_render::RenderScene;
use fenestra_scene::{Backend, Scene};

#[test]
fn probabilities_sum_to_one_and_picks_follow_them() {
    let scene = Scene::build(many_lights(), Backend::Obvhs).expect("scene");
    let lights = Lights::new(&scene);
    let bvh = LightBvh::new(&scene, &lights);
    let mut rng = Rng::new(3);
    let points = test_points(&mut rng);
    // The Sidak-corrected 1% level over the points tested.
    let alpha = 1.0 - 0.99f64.powf(1.0 / points.len() as f64);
    for (p, n) in points {
        let ctx = LightContext {
            p,
            n,
            sample: &SAMPLE,
        };
        // A subtree whose children both bound to zero here holds no light that can reach
        // the point: a descent into it picks nothing, so the probabilities may sum to less
        // than one by that much (a lost sample, never a bias).
        picks_follow_pmf(&bvh, &ctx, lights.lights.len(), &mut rng, alpha);
    }
}

#[test]
fn af_hf_renders_the_same_image_with_the_bvh_as_with_power_selection() {
    agrees_with_power_selection(bvh_af_hf);
}

#[test]
fn a_splitting_tree_picks_each_light_as_often_as_its_probability_says() {
    let scene = Scene::build(many_lights(), Backend::Obvhs).expect("scene");
    let lights = Lights::new(&scene);
    let bvh = LightBvh::new(&scene, &lights).with_splitting(4.0);
    let mut rng = Rng::new(11);
    let mut split_somewhere = false;
    for (p, n) in test_points(&mut rng) {
        let ctx = LightContext {
            p,
            n,
            sample: &SAMPLE,
        };
        // Each light is in at most one pick of an estimate, with probability pmf.
        const DRAWS: usize = 100_000;
        let mut counts = vec![0usize; lights.lights.len()];
        let mut picks_total = 0;
        for _ in 0..DRAWS {
            let mut picks = Picks::default();
            bvh.sample_all(&ctx, rng.next_f32(), &mut picks);
            picks_total += picks.as_slice().len();
            for &(light, q) in picks.as_slice() {
                let pmf = bvh.pmf(&ctx, light);
                assert!(
                    (q - pmf).abs() <= 1e-4 * pmf.max(1e-3),
                    "at {p}: pick of light {light} with {q}, pmf {pmf}"
                );
                counts[light] += 1;
            }
        }
        split_somewhere |= picks_total > DRAWS;
        for (light, &c) in counts.iter().enumerate() {
            let e = DRAWS as f64 * f64::from(bvh.pmf(&ctx, light));
            let sd = (e * (1.0 - e / DRAWS as f64)).max(0.0).sqrt();
            assert!(
                (c as f64 - e).abs() <= 5.0 * sd + 3.0,
                "at {p}: light {light} picked {c} times, expected {e:.0}"
            );
        }
    }
    assert!(split_somewhere, "the tree never split");
}

#[test]
fn af_hf_renders_the_same_image_with_a_splitting_tree() {
    agrees_with_power_selection(|options| {
        PathTracer::new(
            "af_hf",
            LightNextEvent::with_sampler("bvh split", |s: &RenderScene| {
                Box::new(LightBvh::new(&s.scene, &s.lights).with_splitting(4.0))
            }),
            options,
        )
    });
}
