//! lp_hf must agree with af_hf within their standard errors, whatever the portals: exact,
//! half-size (BSDF sampling covers the rest), four times too large (a wrong MIS weight on
//! either technique would show), mixed with light sampling (by power or by the light BVH),
//! and behind thin glass.

use fenestra_builtin as builtin;
use fenestra_core::mis::MisHeuristic;
use fenestra_core::{Rgb, Vec3};
use fenestra_manylights::LightBvh;
use fenestra_portals::{lp_hf, PortalChoice, PortalOptions, PortalSampling, PortalSource};
use fenestra_render::integrator::{af_hf, hf, LightNextEvent, PathOptions};
use fenestra_render::light::LightSelection;
use fenestra_render::{render_image, Film, Integrator, RenderScene, RenderSettings};
use fenestra_scene::light::{EnvironmentDesc, LightDesc};
use fenestra_scene::{Backend, Scene, SceneDesc};

const SIZE: u32 = 32;

fn render(desc: SceneDesc, integrator: &mut dyn Integrator, spp: u32) -> Film {
    let scene = RenderScene::new(Scene::build(desc, Backend::default()).expect("scene"));
    let settings = RenderSettings {
        first_sample: 0,
        spp,
        time_limit: None,
        seed: 11,
    };
    render_image(integrator, &scene, SIZE, SIZE, &settings)
        .expect("render")
        .0
}

fn path(mis: MisHeuristic, depth: u32) -> PathOptions {
    PathOptions {
        max_depth: depth,
        mis,
        ..PathOptions::default()
    }
}

fn portals(options: PortalOptions, mis: MisHeuristic, depth: u32) -> impl Integrator {
    lp_hf(
        path(mis, depth),
        options,
        PortalSource::Scene,
        LightNextEvent::new(LightSelection::Power),
    )
    .expect("lp_hf")
}

fn assert_agree(label: &str, a: &Film, b: &Film) {
    let t = fenestra_eval::agreement(&a.estimate(), &b.estimate(), 0.01, 8).expect("sizes");
    assert!(t.passed(), "{label}: {t:?}");
}

/// `desc` with each portal scaled about its centre by `scale` along both edges.
fn scaled(mut desc: SceneDesc, scale: f32) -> SceneDesc {
    for quad in &mut desc.portals {
        let c = quad.iter().fold(Vec3::ZERO, |a, &p| a + p) / 4.0;
        quad.iter_mut().for_each(|p| *p = c + (*p - c) * scale);
    }
    desc
}

#[test]
fn lp_hf_agrees_with_af_hf_with_exact_small_and_large_portals() {
    let power = MisHeuristic::Power { beta: 2.0 };
    let balance = MisHeuristic::Balance;
    for scene in ["box-hole", "box-hole-sky"] {
        for depth in [2, 4] {
            let load = || builtin::load(scene).expect("builtin");
            let af = render(
                load(),
                &mut af_hf(path(power, depth), LightSelection::Power),
                512,
            );
            let cases = [
                ("exact portals", 1.0, kept_portals(), power, 256),
                ("half-size portals", 0.5, kept_portals(), balance, 512),
                ("4x portals", 4.0, kept_portals(), balance, 512),
                // The seed's rules: area sampling, uniform choice.
                (
                    "half-size portals by area",
                    0.5,
                    PortalOptions {
                        sampling: PortalSampling::Area,
                        choice: PortalChoice::Uniform,
                        ..Default::default()
                    },
                    power,
                    512,
                ),
                // Half the samples from the light sampler: the mixture density must count
                // both techniques.
                (
                    "half-size portals mixed with light sampling",
                    0.5,
                    PortalOptions {
                        light_mix: 0.5,
                        choice: PortalChoice::Facing,
                        ..Default::default()
                    },
                    power,
                    512,
                ),
            ];
            for (what, scale, options, mis, spp) in cases {
                let lp = render(
                    scaled(load(), scale),
                    &mut portals(options, mis, depth),
                    spp,
                );
                assert_agree(
                    &format!("{scene}: af_hf vs lp_hf with {what}, depth {depth}"),
                    &af,
                    &lp,
                );
            }
            // The light share drawn from the light BVH instead of by power.
            let bvh = LightNextEvent::with_sampler("bvh", |s: &RenderScene| {
                Box::new(LightBvh::new(&s.scene, &s.lights))
            });
            let options = PortalOptions {
                light_mix: 0.5,
                ..Default::default()
            };
            let mut lp =
                lp_hf(path(power, depth), options, PortalSource::Scene, bvh).expect("lp_hf");
            let lp = render(scaled(load(), 0.5), &mut lp, 512);
            assert_agree(
                &format!("{scene}: af_hf vs lp_hf mixed with the light BVH, depth {depth}"),
                &af,
                &lp,
            );
        }
    }
}

#[test]
fn light_through_thin_glass_agrees_between_bsdf_and_portal_sampling() {
    // Portal rays pass the pane with its transmittance; BSDF sampling passes it by sampling
    // transmission.
    let power = MisHeuristic::Power { beta: 2.0 };
    for scene in ["box-hole", "box-hole-sky"] {
        for depth in [2, 4] {
            let load = || builtin::glazed(builtin::load(scene).expect("builtin"));
            let hf = render(load(), &mut hf(path(power, depth)), 2048);
            let lp = render(load(), &mut portals(kept_portals(), power, depth), 256);
            assert_agree(
                &format!("glazed {scene}: hf vs lp_hf, depth {depth}"),
                &hf,
                &lp,
            );
        }
    }
}

/// Behind a refracting pane (the 8 mm slab of the glazed rooms), portal probes pass the
/// glass by refraction and the path keeps its vertex before the glass for MIS: lp_hf must
/// agree with af_hf (whose shadow rays stop at the slab: all light beyond it comes from BSDF
/// rays) at path lengths 3 (nothing passes the slab and reaches a light: the probe's
/// refractions are cut by the length left) to 6, over the image, 8x8 regions and the image
/// mean (3.5 standard errors, about 0.3-0.5% here), with the sky and with an area light
/// outside and a blind.
#[test]
fn light_through_refracting_glass_agrees_between_bsdf_and_portal_sampling() {
    refracting_glass_agreement(4096);
}

/// The same at 16 times the samples: image means to 0.06-0.12% (1.2 minutes a room and
/// path length; `cargo test --release -p fenestra-portals --test agreement -- --ignored`).
#[test]
#[ignore = "heavy: about 10 minutes"]
fn light_through_refracting_glass_agrees_to_a_tenth_of_a_percent() {
    refracting_glass_agreement(65536);
}

/// af_hf at `spp` against lp_hf at a quarter of it, the glazed rooms' window given as the
/// portal.
fn refracting_glass_agreement(spp: u32) {
    let power = MisHeuristic::Power { beta: 2.0 };
    let (lo, hi) = builtin::glazed::WINDOW;
    let window = [
        Vec3::new(lo[0], 0.0, lo[1]),
        Vec3::new(hi[0], 0.0, lo[1]),
        Vec3::new(hi[0], 0.0, hi[1]),
        Vec3::new(lo[0], 0.0, hi[1]),
    ];
    for scene in ["room-glazed-sky", "room-glazed-blind"] {
        let load = || SceneDesc {
            portals: vec![window],
            ..builtin::load(scene).expect("builtin")
        };
        for depth in 3..=6 {
            let af = render(
                load(),
                &mut af_hf(path(power, depth), LightSelection::Power),
                spp,
            );
            let lp = render(load(), &mut portals(kept_portals(), power, depth), spp / 4);
            let label = format!("{scene}: af_hf vs lp_hf, depth {depth}");
            assert_agree(&label, &af, &lp);
            let shift = fenestra_eval::mean_shift(&af.estimate(), &lp.estimate()).expect("sizes");
            eprintln!("{label}: {shift:?}");
            assert!(shift.z().abs() < 3.5, "{label}: {shift:?}");
        }
    }
}

#[test]
fn lp_hf_refuses_a_scene_without_portals_and_a_bad_mixture() {
    let scene = RenderScene::new(
        Scene::build(
            builtin::load("cornell-box").expect("builtin"),
            Backend::default(),
        )
        .expect("scene"),
    );
    let settings = RenderSettings {
        first_sample: 0,
        spp: 1,
        time_limit: None,
        seed: 0,
    };
    let mut lp = portals(kept_portals(), MisHeuristic::Balance, 2);
    let Err(e) = render_image(&mut lp, &scene, 4, 4, &settings) else {
        panic!("rendered without portals");
    };
    assert_eq!(
        e.to_string(),
        "lp_hf needs light portals and the scene has none"
    );
    let bad = PortalOptions {
        light_mix: 1.5,
        ..Default::default()
    };
    let Err(e) = lp_hf(
        PathOptions::default(),
        bad,
        PortalSource::Scene,
        LightNextEvent::new(LightSelection::Power),
    ) else {
        panic!("a mixture of 1.5 was accepted");
    };
    assert!(e.to_string().contains("must lie in [0, 1], got 1.5"), "{e}");
    // A mixture draws one light at a time: the default selection, which may split, becomes
    // power selection; a sampler that splits by choice is refused.
    let mix = PortalOptions {
        light_mix: 0.5,
        ..Default::default()
    };
    let with = |selection| {
        lp_hf(
            PathOptions::default(),
            mix,
            PortalSource::Scene,
            LightNextEvent::new(selection),
        )
    };
    let mixed = with(LightSelection::Auto).expect("the default");
    assert_eq!(mixed.settings()["light_selection"], "power");
    let Err(e) = with(LightSelection::Split) else {
        panic!("a splitting sampler was accepted in a mixture");
    };
    assert!(e.to_string().contains("draws one light at a time"), "{e}");
}

/// Under `--sky`'s sky and sun (75 degrees up: its patch lands on the floor), lp_hf leaves the
/// sun to its own light sampling, at every vertex or (compact_share) instead of the portals at
/// some, and a BSDF ray that meets it is weighted against that sampling alone: with indirect
/// light (path length 4) lp_hf, alone and mixed with light sampling, agrees with af_hf over the image and 8x8 regions, and their image
/// means agree within 3.5 standard errors (a standard error of about 0.45%: af_hf finds the
/// sun's bounce light only by the BSDF's rays; the direct sun is checked to 5e-4 against its
/// integral in analytic.rs).
#[test]
fn lp_hf_agrees_with_af_hf_under_the_sky_and_sun() {
    let sky = fenestra_scene::sky::Sky {
        turbidity: 3.0,
        albedo: 0.3,
        elevation_deg: 75.0,
        azimuth_deg: 30.0,
    };
    let load = || {
        builtin::load("box-hole-sky")
            .expect("builtin")
            .with_sky(&sky, Vec3::Z, 0.0, 1.0)
            .expect("a valid sky")
    };
    let power = MisHeuristic::Power { beta: 2.0 };
    let af = render(
        load(),
        &mut af_hf(path(power, 4), LightSelection::Power),
        2048,
    );
    for (what, light_mix, compact_share) in [
        ("portals and the sun at every vertex", 0.0, None),
        ("portals mixed with light sampling", 0.5, None),
        ("the sun or else the portals at a vertex", 0.0, Some(0.3)),
        (
            "the sun or else portals mixed with light sampling",
            0.5,
            Some(0.6),
        ),
    ] {
        let options = PortalOptions {
            light_mix,
            compact_share,
            ..kept_portals()
        };
        let lp = render(load(), &mut portals(options, power, 4), 2048);
        let label = format!("box-hole-sky under --sky: af_hf vs lp_hf with {what}");
        assert_agree(&label, &af, &lp);
        let shift = fenestra_eval::mean_shift(&af.estimate(), &lp.estimate()).expect("sizes");
        eprintln!("{label}: {shift:?}");
        assert!(shift.z().abs() < 3.5, "{label}: {shift:?}");
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

/// The kitchen with daylight behind the camera and a sun of its own besides (a compact light
/// at infinity, which lp_hf samples at every vertex where it keeps portals).
fn kitchen_with_a_sun() -> SceneDesc {
    let mut desc = builtin::load("kitchen-72-env").expect("builtin");
    desc.lights
        .push(LightDesc::Environment(EnvironmentDesc::Sun {
            direction: Vec3::new(0.3, -1.0, 0.5).normalize(),
            radiance: Rgb::splat(2.0e4),
            half_angle: 0.0046,
        }));
    desc
}

/// Where estimation finds no portal carrying light (the Cornell box: its light hangs inside) or
/// the measurement before rendering finds light sampling the more efficient (the kitchen with
/// daylight behind the camera: its 72 downlights are most of what the camera sees), lp_hf
/// samples as af_hf does: the same image, bit for bit (with a sun in the kitchen, the light
/// sampler it keeps is af_hf's, not the one that takes the sun at every vertex).
#[test]
fn lp_hf_without_paying_portals_renders_as_af_hf() {
    let power = MisHeuristic::Power { beta: 2.0 };
    type Load = fn() -> SceneDesc;
    let scenes: [(&str, Load); 2] = [
        ("cornell-box", || {
            builtin::load("cornell-box").expect("builtin")
        }),
        ("kitchen with a sun", kitchen_with_a_sun),
    ];
    for (scene, load) in scenes {
        let af = render(load(), &mut af_hf(path(power, 4), LightSelection::Power), 8);
        // Untimed: the photons then depend on nothing but the parameters.
        let mut params = fenestra_portals::estimate::EstimateParams::default();
        params.photons.time_limit = None;
        let estimated = PortalSource::Estimated {
            params,
            cache: None,
        };
        let mut lp = lp_hf(
            path(power, 4),
            PortalOptions::default(),
            estimated,
            LightNextEvent::new(LightSelection::Power),
        )
        .expect("lp_hf");
        let lp = render(load(), &mut lp, 8);
        assert!(
            af.image().pixels == lp.image().pixels,
            "{scene}: lp_hf differs from af_hf"
        );
    }
}
