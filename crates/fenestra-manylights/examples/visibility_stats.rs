//! Visibility statistics (seed 004 Table 4.4): of each built-in many-light scene's lights
//! (those light selection chooses between: each emissive triangle) and sky regions (the 300
//! regions ias cuts an environment into), how many light some point seen in a 160x90 image
//! (per viewpoint), and how many light the point seen through each pixel on average (per
//! pixel). A light or region lights a point when one of 8 random points on it (directions
//! in it) is above the point's surface, sends light there and is not blocked (thin glass
//! lets light through). Prints a Markdown table.
//!
//! cargo run --release -p fenestra-manylights --example visibility_stats [-- SCENE...]

mod common;

use fenestra_builtin as builtin;
use fenestra_core::{Ray, Rng, Vec2, Vec3};
use fenestra_manylights::sky;
use fenestra_render::light::Light;
use fenestra_render::RenderScene;
use fenestra_scene::{Backend, Scene};
use rayon::prelude::*;

/// Random points (directions) tried on each light (region).
const TRIES: usize = 8;
/// Sky regions, as ias makes them.
const REGIONS: usize = 300;

/// What one image row saw: which lights and regions lit some point, how many lit each
/// point in all, and its points.
struct Row {
    seen_l: Vec<bool>,
    seen_r: Vec<bool>,
    lit_l: u64,
    lit_r: u64,
    points: u64,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let names = common::scene_names();
    println!("| scene | lights | sky regions | lights per viewpoint | regions per viewpoint | lights per pixel | regions per pixel | combined per pixel |");
    println!("|---|---|---|---|---|---|---|---|");
    for name in names {
        let scene = RenderScene::new(Scene::build(builtin::load(&name)?, Backend::default())?);
        // Every light light selection chooses between (each emissive triangle), sky aside.
        let light_source: Vec<Option<usize>> = {
            let mut next = 0;
            scene
                .lights
                .lights
                .iter()
                .map(|l| {
                    (!matches!(l, Light::Environment(_))).then(|| {
                        next += 1;
                        next - 1
                    })
                })
                .collect()
        };
        let sources = light_source.iter().flatten().count();
        let regions = if scene.lights.environments.is_empty() {
            Vec::new()
        } else {
            sky::regions(&scene.lights, REGIONS)
        };
        let (w, h) = (160u32, 90u32);
        let rows: Vec<Row> = (0..h)
            .into_par_iter()
            .map(|y| {
                let mut rng = Rng::new(0x5eed ^ u64::from(y));
                let mut seen_l = vec![false; sources];
                let mut seen_r = vec![false; regions.len()];
                let (mut lit_l, mut lit_r, mut points) = (0u64, 0u64, 0u64);
                let mut here_l = vec![false; sources];
                for x in 0..w {
                    let ray = scene.scene.camera.generate_ray(
                        Vec2::new(x as f32 + 0.5, y as f32 + 0.5),
                        w,
                        h,
                    );
                    let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
                        continue;
                    };
                    let si = scene.scene.interaction(&ray, &hit);
                    let n = si.ng * -si.ng.dot(ray.d).signum();
                    let p = si.spawn(n);
                    points += 1;
                    here_l.fill(false);
                    for (i, light) in scene.lights.lights.iter().enumerate() {
                        let Some(s) = light_source[i] else { continue };
                        if here_l[s] {
                            continue;
                        }
                        let lit = (0..TRIES).any(|_| {
                            let Some(ls) = light.sample_li(&scene.scene, p, rng.next_2d()) else {
                                return false;
                            };
                            let tmax = ls
                                .point
                                .map_or(f32::INFINITY, |q| (q - p).length() * (1.0 - 1e-4));
                            ls.wi.dot(n) > 0.0
                                && !ls.li.is_black()
                                && !scene.transmittance(Ray::new(p, ls.wi), tmax).is_black()
                        });
                        here_l[s] = lit;
                    }
                    for (s, &lit) in here_l.iter().enumerate() {
                        seen_l[s] |= lit;
                        lit_l += u64::from(lit);
                    }
                    for (r, region) in regions.iter().enumerate() {
                        let lit = (0..TRIES).any(|_| {
                            let d: Vec3 = region.sample(rng.next_2d());
                            d.dot(n) > 0.0
                                && !scene
                                    .transmittance(Ray::new(p, d), f32::INFINITY)
                                    .is_black()
                        });
                        seen_r[r] |= lit;
                        lit_r += u64::from(lit);
                    }
                }
                Row {
                    seen_l,
                    seen_r,
                    lit_l,
                    lit_r,
                    points,
                }
            })
            .collect();
        let mut seen_l = vec![false; sources];
        let mut seen_r = vec![false; regions.len()];
        let (mut lit_l, mut lit_r, mut points) = (0u64, 0u64, 0u64);
        for row in rows {
            seen_l.iter_mut().zip(row.seen_l).for_each(|(a, b)| *a |= b);
            seen_r.iter_mut().zip(row.seen_r).for_each(|(a, b)| *a |= b);
            lit_l += row.lit_l;
            lit_r += row.lit_r;
            points += row.points;
        }
        let count = |v: &[bool]| v.iter().filter(|&&b| b).count();
        let pct = |a: f64, of: usize| {
            if of == 0 {
                "N/A".to_string()
            } else {
                format!("{a:.1} ({:.1}%)", 100.0 * a / of as f64)
            }
        };
        let per_point = |n: u64| n as f64 / points.max(1) as f64;
        println!(
            "| {name} | {sources} | {} | {} | {} | {} | {} | {} |",
            regions.len(),
            pct(count(&seen_l) as f64, sources),
            pct(count(&seen_r) as f64, regions.len()),
            pct(per_point(lit_l), sources),
            pct(per_point(lit_r), regions.len()),
            pct(per_point(lit_l + lit_r), sources + regions.len()),
        );
    }
    Ok(())
}
