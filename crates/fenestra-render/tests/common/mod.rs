//! Helpers shared by the render integration tests.
#![allow(dead_code)] // each test binary uses a subset

use fenestra_render::integrator::{self, IntegratorOptions, NoProgress};
use fenestra_render::portal::Portals;
use fenestra_render::{
    Film, LightSelection, RenderControl, RenderScene, RenderSettings, RenderStats,
};
use fenestra_scene::{Backend, Scene, SceneDesc};
use std::sync::atomic::AtomicBool;

pub fn render(
    desc: SceneDesc,
    name: &str,
    options: IntegratorOptions,
    size: u32,
    spp: u32,
    seed: u64,
) -> (Film, RenderStats) {
    let portals = Portals::from_quads(&desc.portals);
    let scene = RenderScene::new(
        Scene::build(desc, Backend::default()).expect("scene"),
        LightSelection::Power,
    );
    // "lp_hf_mix": lp_hf with half of its samples from the light sampler (Cycles' mixture).
    let (name, light_mix) = match name {
        "lp_hf_mix" => ("lp_hf", 0.5),
        other => (other, 0.0),
    };
    let integrator = integrator::by_name(name, options, portals, light_mix).expect("integrator");
    let mut film = Film::new(size, size);
    let cancel = AtomicBool::new(false);
    let control = RenderControl::new(&cancel, &NoProgress);
    let stats = integrator.render(
        &scene,
        &mut film,
        &RenderSettings {
            spp,
            time_limit: None,
            seed,
        },
        &control,
    );
    (film, stats)
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
