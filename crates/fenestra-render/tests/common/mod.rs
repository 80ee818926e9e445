//! Helpers shared by the render integration tests.
#![allow(dead_code)] // each test binary uses a subset

use fenestra_render::integrator::{af_hf, hf, PathOptions};
use fenestra_render::light::LightSelection;
use fenestra_render::{render_image, Film, Integrator, RenderScene, RenderSettings, RenderStats};
use fenestra_scene::{Backend, Scene, SceneDesc};

/// `hf` or `af_hf` (with power light selection) by name.
pub fn integrator(name: &str, options: PathOptions) -> Box<dyn Integrator> {
    match name {
        "hf" => Box::new(hf(options)),
        "af_hf" => Box::new(af_hf(options, LightSelection::Power)),
        _ => panic!("no integrator {name} in these tests"),
    }
}

/// Renders `desc` with `integrator` at `size` x `size`.
pub fn render(
    desc: SceneDesc,
    integrator: &mut dyn Integrator,
    size: u32,
    spp: u32,
    seed: u64,
) -> (Film, RenderStats) {
    let scene = RenderScene::new(Scene::build(desc, Backend::default()).expect("scene"));
    let settings = RenderSettings {
        first_sample: 0,
        spp,
        time_limit: None,
        seed,
    };
    render_image(integrator, &scene, size, size, &settings).expect("render")
}

/// Mean and standard error of the red channel over the pixels in [x0, x1) x [y0, y1).
pub fn region_mean(film: &Film, x0: u32, x1: u32, y0: u32, y1: u32) -> (f64, f64) {
    let (mut sum, mut var) = (0.0, 0.0);
    let mut n = 0.0;
    for y in y0..y1 {
        for x in x0..x1 {
            let p = &film.pixels[(y * film.width + x) as usize];
            sum += p.mean()[0];
            var += p.variance_of_mean()[0];
            n += 1.0;
        }
    }
    (sum / n, var.sqrt() / n)
}

/// Fails unless `a` and `b` agree within their standard errors over the whole image and
/// over every 8x8 region (z-test at 1%).
pub fn assert_agree(label: &str, a: &Film, b: &Film) {
    let t = fenestra_eval::agreement(&a.estimate(), &b.estimate(), 0.01, 8).expect("sizes");
    assert!(t.passed(), "{label}: {t:?}");
}
