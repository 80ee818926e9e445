//! The light BVH as a light sampler: its probabilities sum to one, its picks follow them
//! (chi-square), it reports the probability of what it picks, and af_hf renders the same
//! image with it as with power selection, the same with one thread as with two.

mod common;

use common::{bvh_af_hf, many_lights, render};
use fenestra_builtin as builtin;
use fenestra_core::{warp, Rng, Vec3};
use fenestra_manylights::LightBvh;
use fenestra_render::driver::SampleContext;
use fenestra_render::integrator::{af_hf, PathOptions};
use fenestra_render::light::{LightContext, LightSampler, LightSelection, Lights};
use fenestra_scene::{Backend, Scene};
use statrs::distribution::{ChiSquared, ContinuousCDF};

fn context(p: Vec3, n: Vec3, sample: &SampleContext) -> LightContext<'_> {
    LightContext { p, n, sample }
}

#[test]
fn probabilities_sum_to_one_and_picks_follow_them() {
    let scene = Scene::build(many_lights(), Backend::Obvhs).expect("scene");
    let lights = Lights::new(&scene);
    let bvh = LightBvh::new(&scene, &lights);
    let sample = SampleContext {
        x: 0,
        y: 0,
        width: 1,
        height: 1,
        block: 0,
        pass: 0,
        index: 0,
    };
    let mut rng = Rng::new(3);
    let points: Vec<(Vec3, Vec3)> = (0..6)
        .map(|k| {
            let p = Vec3::new(
                6.0 * rng.next_f32() - 3.0,
                6.0 * rng.next_f32() - 3.0,
                3.0 * rng.next_f32(),
            );
            // One point receives from every side (a zero normal).
            let n = if k == 0 {
                Vec3::ZERO
            } else {
                warp::square_to_uniform_sphere(rng.next_2d())
            };
            (p, n)
        })
        .collect();
    // The Sidak-corrected 1% level over the points tested.
    let alpha = 1.0 - 0.99f64.powf(1.0 / points.len() as f64);
    for (p, n) in points {
        let ctx = context(p, n, &sample);
        let pmf: Vec<f64> = (0..lights.lights.len())
            .map(|i| f64::from(bvh.pmf(&ctx, i)))
            .collect();
        // A subtree whose children both bound to zero here holds no light that can reach
        // the point: a descent into it picks nothing, so the probabilities may sum to less
        // than one by that much (a lost sample, never a bias).
        let total: f64 = pmf.iter().sum();
        assert!(
            total <= 1.0 + 1e-4 && total > 0.5,
            "at {p}: probabilities sum to {total}"
        );
        const DRAWS: usize = 200_000;
        // One more bin: no light picked.
        let mut counts = vec![0.0f64; pmf.len() + 1];
        for _ in 0..DRAWS {
            let Some((i, q)) = bvh.sample(&ctx, rng.next_f32()) else {
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
        let expected = pmf.iter().copied().chain([(1.0 - total).max(0.0)]);
        let (mut stat, mut dof, mut pool) = (0.0, 0i64, (0.0, 0.0));
        for (o, e) in counts.iter().zip(expected.map(|p| p * DRAWS as f64)) {
            if e < 1e-6 {
                assert_eq!(*o, 0.0, "something of zero probability was picked");
            } else if e < 5.0 {
                pool = (pool.0 + o, pool.1 + e);
            } else {
                stat += (o - e).powi(2) / e;
                dof += 1;
            }
        }
        if pool.1 > 0.0 {
            stat += (pool.0 - pool.1).powi(2) / pool.1;
            dof += 1;
        }
        let dof = (dof - 1).max(1) as f64;
        let p_value = 1.0 - ChiSquared::new(dof).expect("dof").cdf(stat);
        assert!(
            p_value > alpha,
            "at {p}: chi2 {stat:.1}, {dof} dof, p = {p_value:.2e}"
        );
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
