//! The light BVH as a light sampler: its probabilities sum to one, its picks follow them
//! (chi-square), it reports the probability of what it picks, and af_hf renders the same
//! image with it as with power selection, the same with one thread as with two.

mod common;

use common::{bvh_af_hf, many_lights, picks_follow_pmf, render, test_points, SAMPLE};
use fenestra_builtin as builtin;
use fenestra_core::Rng;
use fenestra_manylights::LightBvh;
use fenestra_render::integrator::{af_hf, PathOptions};
use fenestra_render::light::{LightContext, LightSelection, Lights};
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
    for name in ["many lights", "kitchen-72-env"] {
        let scene = || match name {
            "many lights" => many_lights(),
            other => builtin::load(other).expect("builtin"),
        };
        let options = PathOptions {
            max_depth: 3,
            ..Default::default()
        };
        let power = render(scene(), &mut af_hf(options, LightSelection::Power), 256, 2);
        let bvh = render(scene(), &mut bvh_af_hf(options), 256, 2);
        let t =
            fenestra_eval::agreement(&power.estimate(), &bvh.estimate(), 0.01, 8).expect("sizes");
        assert!(t.passed(), "{name}: {t:?}");
        let one = render(scene(), &mut bvh_af_hf(options), 16, 1);
        let two = render(scene(), &mut bvh_af_hf(options), 16, 2);
        assert_eq!(
            one.estimate().mean.pixels,
            two.estimate().mean.pixels,
            "{name}: 1 and 2 threads"
        );
    }
}
