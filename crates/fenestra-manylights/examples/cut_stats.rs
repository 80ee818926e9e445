//! Clusters per cut (seed 004 Table 4.5): the forest built over each built-in many-light
//! scene, and the cut at the camera hit of every pixel of a 160x90 image (one ray per pixel
//! centre), with the seed's 0.02 sr bound. Prints a Markdown table.
//!
//! cargo run --release -p fenestra-manylights --example cut_stats [-- SCENE...]

mod common;

use fenestra_builtin as builtin;
use fenestra_core::Vec2;
use fenestra_manylights::{Forest, CUT_SOLID_ANGLE};
use fenestra_render::light::Lights;
use fenestra_scene::{Backend, Scene};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let names = common::scene_names();
    println!(
        "| scene | lights in trees | trees | build s | mean clusters per cut | % of lights | max |"
    );
    println!("|---|---|---|---|---|---|---|");
    for name in names {
        let scene = Scene::build(builtin::load(&name)?, Backend::default())?;
        let lights = Lights::new(&scene);
        let start = Instant::now();
        let forest = Forest::new(&scene, &lights);
        let build = start.elapsed().as_secs_f64();
        let finite = lights.lights.len() - forest.infinite.len();
        let (w, h) = (160, 90);
        let (mut sum, mut count, mut max) = (0usize, 0usize, 0usize);
        let mut cut = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let ray =
                    scene
                        .camera
                        .generate_ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), w, h);
                let Some(hit) = scene.intersect(&ray, f32::INFINITY) else {
                    continue;
                };
                let si = scene.interaction(&ray, &hit);
                let n = si.ng * -si.ng.dot(ray.d).signum();
                forest.cut(si.spawn(n), n, CUT_SOLID_ANGLE, &mut cut);
                sum += cut.len();
                max = max.max(cut.len());
                count += 1;
            }
        }
        let mean = sum as f64 / count.max(1) as f64;
        println!(
            "| {name} | {finite} | {} | {build:.3} | {mean:.1} | {:.1}% | {max} |",
            forest.roots.len(),
            100.0 * mean / finite.max(1) as f64
        );
    }
    Ok(())
}
