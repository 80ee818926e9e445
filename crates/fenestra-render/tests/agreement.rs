//! Different estimators of the same image must agree within their standard errors: `hf`
//! and `af_hf` (balance and power heuristics) on builtin:box-hole at path lengths 2 and 4,
//! and through thin glass. (lp_hf's agreement tests are in fenestra-portals.)

mod common;

use common::assert_agree;
use fenestra_builtin as builtin;
use fenestra_core::mis::MisHeuristic;
use fenestra_render::integrator::PathOptions;
use fenestra_render::Film;
use fenestra_scene::SceneDesc;

const SIZE: u32 = 32;

fn options(mis: MisHeuristic, depth: u32) -> PathOptions {
    PathOptions {
        max_depth: depth,
        mis,
        ..PathOptions::default()
    }
}

fn render(desc: SceneDesc, name: &str, mis: MisHeuristic, depth: u32, spp: u32) -> Film {
    let mut integrator = common::integrator(name, options(mis, depth));
    common::render(desc, integrator.as_mut(), SIZE, spp, 11).0
}

fn box_hole() -> SceneDesc {
    builtin::load("box-hole").expect("builtin")
}

#[test]
fn hf_and_af_hf_agree_on_box_hole() {
    let power = MisHeuristic::Power { beta: 2.0 };
    for depth in [2, 4] {
        let hf = render(box_hole(), "hf", power, depth, 2048);
        let balance = render(box_hole(), "af_hf", MisHeuristic::Balance, depth, 256);
        let power2 = render(box_hole(), "af_hf", power, depth, 256);
        assert_agree(
            &format!("hf vs af_hf balance, depth {depth}"),
            &hf,
            &balance,
        );
        assert_agree(&format!("hf vs af_hf power, depth {depth}"), &hf, &power2);
        assert_agree(
            &format!("balance vs power, depth {depth}"),
            &balance,
            &power2,
        );
    }
}

#[test]
fn the_agreement_test_detects_a_real_difference() {
    // Path length 4 carries more light than 2; the comparison must see that.
    let power = MisHeuristic::Power { beta: 2.0 };
    let (a, b) = (
        render(box_hole(), "af_hf", power, 2, 256),
        render(box_hole(), "af_hf", power, 4, 256),
    );
    let t = fenestra_eval::agreement(&a.estimate(), &b.estimate(), 0.01, 8).expect("sizes");
    assert!(!t.whole.passed && t.whole.min_p < 1e-20, "{t:?}");
}

#[test]
fn light_through_thin_glass_agrees_between_bsdf_and_light_sampling() {
    // Shadow rays pass the pane with its transmittance; BSDF sampling passes it by sampling
    // transmission. hf uses no shortcut, so it checks light sampling.
    let power = MisHeuristic::Power { beta: 2.0 };
    for scene in ["box-hole", "box-hole-sky"] {
        for depth in [2, 4] {
            let load = || builtin::glazed(builtin::load(scene).expect("builtin"));
            let hf = render(load(), "hf", power, depth, 2048);
            let af = render(load(), "af_hf", power, depth, 256);
            assert_agree(
                &format!("glazed {scene}: hf vs af_hf, depth {depth}"),
                &hf,
                &af,
            );
            // The pane takes about 8% (R' at normal incidence, more at grazing angles): a
            // check that the light really went through glass.
            let open = render(
                builtin::load(scene).expect("builtin"),
                "af_hf",
                power,
                depth,
                256,
            );
            let (g, o) = (
                common::region_mean(&af, 0, SIZE, 0, SIZE).0,
                common::region_mean(&open, 0, SIZE, 0, SIZE).0,
            );
            assert!((0.8..0.93).contains(&(g / o)), "glazed/open = {}", g / o);
        }
    }
}
