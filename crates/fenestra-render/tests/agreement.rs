//! Different estimators of the same image must agree within their standard errors: `hf`
//! and `af_hf` (balance and power heuristics) on builtin:box-hole at path lengths 2 and 4;
//! `lp_hf` and `af_hf` on box-hole and box-hole-sky with exact and too-small portals.

mod common;

use fenestra_core::mis::MisHeuristic;
use fenestra_core::Vec3;
use fenestra_render::integrator::IntegratorOptions;
use fenestra_render::Film;
use fenestra_scene::{builtin, SceneDesc};

const SIZE: u32 = 32;

fn render(name: &str, mis: MisHeuristic, depth: u32, spp: u32) -> Film {
    render_scene(
        builtin::load("box-hole").expect("builtin"),
        name,
        mis,
        depth,
        spp,
    )
}

fn render_scene(desc: SceneDesc, name: &str, mis: MisHeuristic, depth: u32, spp: u32) -> Film {
    let options = IntegratorOptions {
        max_depth: depth,
        mis,
        rr_depth: 3,
    };
    common::render(desc, name, options, SIZE, spp, 11).0
}

/// z-scores of the differences of the image mean and of each 8x8 region's mean.
fn z_scores(a: &Film, b: &Film) -> (f64, Vec<f64>) {
    let z = |(ma, sa): (f64, f64), (mb, sb): (f64, f64)| (ma - mb) / (sa * sa + sb * sb).sqrt();
    let whole = z(
        common::region_mean(a, 0, SIZE, 0, SIZE),
        common::region_mean(b, 0, SIZE, 0, SIZE),
    );
    let mut regions = Vec::new();
    for by in (0..SIZE).step_by(8) {
        for bx in (0..SIZE).step_by(8) {
            regions.push(z(
                common::region_mean(a, bx, bx + 8, by, by + 8),
                common::region_mean(b, bx, bx + 8, by, by + 8),
            ));
        }
    }
    (whole, regions)
}

fn assert_agree(label: &str, a: &Film, b: &Film) {
    let (whole, regions) = z_scores(a, b);
    assert!(
        whole.abs() < 3.0,
        "{label}: image means differ by {whole:.2} standard errors"
    );
    // Each of the 16 regions within 3 standard errors; by chance about 0.04 of them exceed it,
    // so one exceedance is tolerated, none beyond 4.
    let beyond3 = regions.iter().filter(|z| z.abs() >= 3.0).count();
    let worst = regions.iter().fold(0.0f64, |m, z| m.max(z.abs()));
    assert!(
        beyond3 <= 1 && worst < 4.0,
        "{label}: region z-scores {regions:.2?}"
    );
}

#[test]
fn hf_and_af_hf_agree_on_box_hole() {
    let power = MisHeuristic::Power { beta: 2.0 };
    for depth in [2, 4] {
        let hf = render("hf", power, depth, 2048);
        let balance = render("af_hf", MisHeuristic::Balance, depth, 256);
        let power2 = render("af_hf", power, depth, 256);
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
    let (whole, _) = z_scores(
        &render("af_hf", power, 2, 256),
        &render("af_hf", power, 4, 256),
    );
    assert!(whole.abs() > 10.0, "z = {whole}");
}

/// `desc` with each portal scaled about its centre by `scale` along both edges.
fn shrunk(mut desc: SceneDesc, scale: f32) -> SceneDesc {
    for quad in &mut desc.portals {
        let c = quad.iter().fold(Vec3::ZERO, |a, &p| a + p) / 4.0;
        quad.iter_mut().for_each(|p| *p = c + (*p - c) * scale);
    }
    desc
}

#[test]
fn lp_hf_agrees_with_af_hf_with_exact_small_and_large_portals() {
    // With MIS the portal estimator stays unbiased when the portals miss part of the opening:
    // BSDF sampling covers the rest.
    let power = MisHeuristic::Power { beta: 2.0 };
    for scene in ["box-hole", "box-hole-sky"] {
        for depth in [2, 4] {
            let load = || builtin::load(scene).expect("builtin");
            let af = render_scene(load(), "af_hf", power, depth, 512);
            let exact = render_scene(load(), "lp_hf", power, depth, 256);
            let small = render_scene(
                shrunk(load(), 0.5),
                "lp_hf",
                MisHeuristic::Balance,
                depth,
                512,
            );
            // Oversized portals make the BSDF technique's MIS weight large: a wrong weight on
            // either technique would show here.
            let large = render_scene(
                shrunk(load(), 4.0),
                "lp_hf",
                MisHeuristic::Balance,
                depth,
                512,
            );
            assert_agree(
                &format!("{scene}: af_hf vs lp_hf, depth {depth}"),
                &af,
                &exact,
            );
            assert_agree(
                &format!("{scene}: af_hf vs lp_hf with half-size portals, depth {depth}"),
                &af,
                &small,
            );
            assert_agree(
                &format!("{scene}: af_hf vs lp_hf with 4x portals, depth {depth}"),
                &af,
                &large,
            );
            // Half the samples from the light sampler, with half-size portals: the mixture
            // density must count both techniques.
            let mixed = render_scene(shrunk(load(), 0.5), "lp_hf_mix", power, depth, 512);
            assert_agree(
                &format!("{scene}: af_hf vs lp_hf mixed with light sampling, depth {depth}"),
                &af,
                &mixed,
            );
        }
    }
}

/// `desc` with a thin glass pane (eta 1.5) filling each portal's opening.
fn glazed(mut desc: SceneDesc) -> SceneDesc {
    use fenestra_scene::{Material, Shape, ShapeKind, TriangleMesh};
    let glass = desc.materials.len();
    desc.materials.push(Material::ThinDielectric { eta: 1.5 });
    for q in desc.portals.clone() {
        let c = (q[0] + q[1] + q[2] + q[3]) / 4.0;
        let pane = TriangleMesh::quad(c, (q[1] - q[0]) * 0.5, (q[3] - q[0]) * 0.5);
        desc.shapes.push(Shape::new(ShapeKind::Mesh(pane), glass));
    }
    desc
}

#[test]
fn light_through_thin_glass_agrees_between_bsdf_light_and_portal_sampling() {
    // Shadow and portal rays pass the pane with its transmittance; BSDF sampling passes it
    // by sampling transmission. hf uses neither shortcut, so it checks both.
    let power = MisHeuristic::Power { beta: 2.0 };
    for scene in ["box-hole", "box-hole-sky"] {
        for depth in [2, 4] {
            let load = || glazed(builtin::load(scene).expect("builtin"));
            let hf = render_scene(load(), "hf", power, depth, 2048);
            let af = render_scene(load(), "af_hf", power, depth, 256);
            let lp = render_scene(load(), "lp_hf", power, depth, 256);
            assert_agree(
                &format!("glazed {scene}: hf vs af_hf, depth {depth}"),
                &hf,
                &af,
            );
            assert_agree(
                &format!("glazed {scene}: hf vs lp_hf, depth {depth}"),
                &hf,
                &lp,
            );
            // The pane takes about 8% (R' at normal incidence, more at grazing angles): a
            // check that the light really went through glass.
            let open = render_scene(
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
