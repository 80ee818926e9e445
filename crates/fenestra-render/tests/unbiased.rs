//! Render tests as Mitsuba 3 does them: each estimator's image, with its per-pixel variance,
//! against a high-sample reference by a per-pixel z-test at alpha = 0.01 with Sidak
//! correction. It must pass for unbiased estimators and fail for biased ones.

mod common;

use fenestra_builtin as builtin;
use fenestra_core::image::Image;
use fenestra_core::mis::MisHeuristic;
use fenestra_eval::z_test;
use fenestra_render::integrator::PathOptions;

const SIZE: u32 = 16;
/// z-tests run on 2x2 pixel blocks: per-pixel variance estimates of rare-event estimators
/// (hf finding a small emitter) are unreliable; block means are closer to normal.
const BLOCK: usize = 2;

fn render(name: &str, mis: MisHeuristic, depth: u32, spp: u32, seed: u64) -> (Image, Image) {
    let options = PathOptions {
        max_depth: depth,
        mis,
        ..PathOptions::default()
    };
    let (film, _) = common::render(
        builtin::load("box-hole").expect("builtin"),
        common::integrator(name, options).as_mut(),
        SIZE,
        spp,
        seed,
    );
    (film.image(), film.variance_image())
}

#[test]
fn estimators_pass_the_z_test_and_biased_ones_fail() {
    let power = MisHeuristic::Power { beta: 2.0 };
    let (reference, ref_var) = render("af_hf", power, 4, 4096, 100);
    for (name, mis, spp) in [
        ("af_hf", power, 256),
        ("af_hf", MisHeuristic::Balance, 256),
        ("hf", power, 2048),
    ] {
        let (img, var) = render(name, mis, 4, spp, 7);
        let t = z_test(&img, &var, &reference, Some(&ref_var), 0.01, BLOCK).expect("sizes");
        assert!(t.passed, "{name} {mis:?}: {t:?}");
    }
    // A path length short of the reference's misses a bounce of light: biased.
    let (short, var) = render("af_hf", power, 3, 256, 7);
    let t = z_test(&short, &var, &reference, Some(&ref_var), 0.01, BLOCK).expect("sizes");
    assert!(!t.passed, "path length 3 against 4 must fail: {t:?}");
    // So is an image 30% too bright (this scene is noisy at 256 spp: a bias of a few percent
    // needs far more samples to show).
    let (mut bright, var) = render("af_hf", power, 4, 256, 7);
    bright.pixels.iter_mut().for_each(|p| *p = *p * 1.3);
    let t = z_test(&bright, &var, &reference, Some(&ref_var), 0.01, BLOCK).expect("sizes");
    assert!(!t.passed, "a 30% bias must fail: {t:?}");
}
