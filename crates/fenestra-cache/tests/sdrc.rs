//! The sdrc integrator against af_hf: as the interpolation error a goes to 0 every shading
//! point gets its own record and the cache's answer must become af_hf's; renders must not
//! depend on the thread count; bad options are refused.

use fenestra_cache::{Sdrc, SdrcOptions};
use fenestra_eval::ztest::agreement;
use fenestra_render::integrator::{af_hf, Integrator, LightNextEvent, PathOptions};
use fenestra_render::light::LightSelection;
use fenestra_render::{render_image, Film, RenderScene, RenderSettings};
use fenestra_scene::{Backend, Scene};

fn teapot_box() -> RenderScene {
    let desc = fenestra_builtin::load("teapot-box").expect("built-in scene");
    RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"))
}

fn path() -> PathOptions {
    PathOptions {
        max_depth: 4,
        ..Default::default()
    }
}

fn sdrc(options: SdrcOptions) -> Sdrc {
    Sdrc::new(options, path(), LightNextEvent::new(LightSelection::Power)).expect("options")
}

fn render(
    integrator: &mut dyn Integrator,
    scene: &RenderScene,
    size: u32,
    spp: u32,
    seed: u64,
) -> Film {
    let settings = RenderSettings {
        spp,
        first_sample: 0,
        time_limit: None,
        seed,
    };
    render_image(integrator, scene, size, size, &settings)
        .expect("render")
        .0
}

#[test]
fn with_a_vanishing_error_the_cache_gives_af_hf_answer() {
    let scene = teapot_box();
    let mut cache = sdrc(SdrcOptions {
        a: 1e-3,
        min_reach: 0.0,
        n: 64,
        ..Default::default()
    });
    let film = render(&mut cache, &scene, 32, 16, 1);
    let cached = cache
        .work_maps()
        .into_iter()
        .find(|m| m.name == "cached")
        .expect("cached map");
    let served = cached.values.iter().filter(|&&v| v > 0.0).count();
    assert!(
        served > 100,
        "the cache served {served} pixels of the teapot"
    );
    let reference = render(
        &mut af_hf(path(), LightSelection::Power),
        &scene,
        32,
        256,
        2,
    );
    let agree = agreement(&film.estimate(), &reference.estimate(), 0.01, 8).expect("same size");
    assert!(agree.passed(), "{agree:#?}");
}

#[test]
fn renders_do_not_depend_on_the_thread_count() {
    let scene = teapot_box();
    let image = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| {
            let mut cache = sdrc(SdrcOptions {
                n: 32,
                ..Default::default()
            });
            render(&mut cache, &scene, 24, 4, 5).image().pixels
        })
    };
    let one = image(1);
    assert!(one.iter().any(|p| p.r > 0.0));
    assert!(one == image(2), "1 and 2 threads differ");
}

#[test]
fn bad_options_are_refused_with_the_option_named() {
    let refused = |options: SdrcOptions| match Sdrc::new(
        options,
        path(),
        LightNextEvent::new(LightSelection::Power),
    ) {
        Ok(_) => panic!("accepted {options:?}"),
        Err(e) => e.to_string(),
    };
    let d = SdrcOptions::default();
    assert!(refused(SdrcOptions { a: 0.0, ..d }).contains("--sdrc-a "));
    assert!(refused(SdrcOptions { a_scale: 0.5, ..d }).contains("--sdrc-a-scale"));
    assert!(refused(SdrcOptions { n: 0, ..d }).contains("--sdrc-n"));
    assert!(refused(SdrcOptions { r_max: 3.0, ..d }).contains("--sdrc-r-max"));
    assert!(refused(SdrcOptions {
        min_reach: -1.0,
        ..d
    })
    .contains("--sdrc-min-reach"));
}
