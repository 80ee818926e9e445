//! `fenestra raybench`: closest-hit and shadow-ray throughput of the ray-query backends on
//! incoherent rays (random origins in the scene bounds, uniform directions) and on coherent
//! camera rays, one ray per query and in packets of eight.

use crate::support::scene_arg;
use anyhow::{bail, Context, Result};
use clap::Args;
use fenestra_core::{warp, Ray, Sampler, Vec2, Vec3};
use fenestra_scene::{Backend, Scene, PACKET};
use rayon::prelude::*;
use serde_json::json;
use std::time::Instant;

#[derive(Args)]
pub struct RaybenchArgs {
    /// builtin:NAME, a pbrt-v4 scene file, or an OBJ/PLY mesh.
    scene: String,
    #[command(flatten)]
    scene_options: scene_arg::SceneOptions,
    /// Number of rays of each kind.
    #[arg(long, default_value_t = 1_000_000)]
    rays: usize,
    /// Timed repetitions; the median is reported.
    #[arg(long, default_value_t = 5)]
    repeat: usize,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Backends to measure, comma-separated (default: all in this build).
    #[arg(long, value_delimiter = ',')]
    bvh: Vec<Backend>,
    /// Print the results as JSON lines.
    #[arg(long)]
    json: bool,
}

/// Closest-hit rays from random points along uniform directions, and shadow segments between
/// pairs of random points, all inside the scene's bounding box.
fn make_rays(scene: &Scene, n: usize) -> (Vec<Ray>, Vec<(Ray, f32)>) {
    let (lo, hi) = scene.bounds();
    let point = |s: &mut Sampler| lo + (hi - lo) * Vec3::new(s.next_1d(), s.next_1d(), s.next_1d());
    let closest = (0..n)
        .map(|i| {
            let mut s = Sampler::new(1, i as u64, 0);
            Ray::new(point(&mut s), warp::square_to_uniform_sphere(s.next_2d()))
        })
        .collect();
    let shadow = (0..n)
        .map(|i| {
            let mut s = Sampler::new(2, i as u64, 0);
            let (a, b) = (point(&mut s), point(&mut s));
            let d = (b - a).length().max(1e-6);
            (Ray::new(a, (b - a) / d), d)
        })
        .collect();
    (closest, shadow)
}

/// Camera rays through the centres of a `width x height` grid of pixels (about `n` of them),
/// ordered by 4x2-pixel tiles so that each packet of eight holds neighbours.
fn camera_rays(scene: &Scene, n: usize) -> Vec<Ray> {
    let width = (((n as f64).sqrt() as u32) / 4).max(1) * 4;
    let height = ((n as u32 / width) / 2).max(1) * 2;
    let mut rays = Vec::with_capacity((width * height) as usize);
    for ty in (0..height).step_by(2) {
        for tx in (0..width).step_by(4) {
            for (dx, dy) in (0..2).flat_map(|dy| (0..4).map(move |dx| (dx, dy))) {
                let film = Vec2::new((tx + dx) as f32 + 0.5, (ty + dy) as f32 + 0.5);
                rays.push(scene.camera.generate_ray(film, width, height));
            }
        }
    }
    rays
}

/// Closest hits among `rays`, one query per ray (`packets` false) or per eight.
fn count_hits(scene: &Scene, rays: &[Ray], packets: bool) -> usize {
    if packets {
        rays.par_chunks_exact(PACKET)
            .map(|c| {
                let packet: [Ray; PACKET] = std::array::from_fn(|i| c[i]);
                let hits = scene.intersect8(&packet, [f32::INFINITY; PACKET]);
                hits.iter().filter(|h| h.is_some()).count()
            })
            .sum()
    } else {
        rays.par_iter()
            .filter(|r| scene.intersect(r, f32::INFINITY).is_some())
            .count()
    }
}

/// Blocked segments among `segments`, one query per segment or per eight.
fn count_blocked(scene: &Scene, segments: &[(Ray, f32)], packets: bool) -> usize {
    if packets {
        segments
            .par_chunks_exact(PACKET)
            .map(|c| {
                let rays: [Ray; PACKET] = std::array::from_fn(|i| c[i].0);
                let blocked = scene.occluded8(&rays, std::array::from_fn(|i| c[i].1));
                blocked.iter().filter(|&&b| b).count()
            })
            .sum()
    } else {
        segments
            .par_iter()
            .filter(|(r, d)| scene.occluded(r, *d))
            .count()
    }
}

/// Runs `f` `n` times; returns its result and the median time in seconds.
fn median_time(n: usize, f: impl Fn() -> usize) -> (usize, f64) {
    let mut result = 0;
    let mut times: Vec<f64> = (0..n)
        .map(|_| {
            let t = Instant::now();
            result = f();
            t.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    (result, times[n / 2])
}

pub fn run(args: RaybenchArgs) -> Result<()> {
    if args.rays == 0 || args.repeat == 0 {
        bail!("--rays and --repeat must be at least 1");
    }
    // Each closest ray takes 24 bytes and each shadow ray 28, kept for the whole benchmark.
    const MAX_RAYS: usize = 100_000_000;
    if args.rays > MAX_RAYS {
        bail!(
            "--rays {} would take {:.1} GB of memory; at most {MAX_RAYS}",
            args.rays,
            args.rays as f64 * 52.0 / 1e9
        );
    }
    let pool = crate::thread_pool(args.threads)?;
    let desc = scene_arg::load(&args.scene, &args.scene_options)?.desc;
    pool.install(|| -> Result<()> {
        let backends = if args.bvh.is_empty() { Backend::available() } else { args.bvh.clone() };
        for backend in backends {
            let t0 = Instant::now();
            let scene = Scene::build(desc.clone(), backend).context("invalid scene")?;
            let build_s = t0.elapsed().as_secs_f64();
            let (closest, shadow) = make_rays(&scene, args.rays);
            let camera = camera_rays(&scene, args.rays);
            let rate = |rays: usize, s: f64| rays as f64 / s / 1e6;
            // Packets take whole groups of eight; the few rays left over are not timed.
            let whole = args.rays / PACKET * PACKET;
            let mut figures = serde_json::Map::new();
            let mut line = Vec::new();
            for packets in [false, true] {
                let suffix = if packets { "8" } else { "" };
                let n = if packets { whole } else { args.rays };
                let (hits, closest_s) =
                    median_time(args.repeat, || count_hits(&scene, &closest[..n], packets));
                let (blocked, shadow_s) =
                    median_time(args.repeat, || count_blocked(&scene, &shadow[..n], packets));
                let (_, camera_s) =
                    median_time(args.repeat, || count_hits(&scene, &camera, packets));
                figures.insert(format!("closest{suffix}_mrays_per_s"), json!(rate(n, closest_s)));
                figures.insert(format!("shadow{suffix}_mrays_per_s"), json!(rate(n, shadow_s)));
                figures.insert(format!("camera{suffix}_mrays_per_s"), json!(rate(camera.len(), camera_s)));
                if !packets {
                    figures.insert("closest_hit_fraction".into(), json!(hits as f64 / n as f64));
                    figures.insert("shadow_blocked_fraction".into(), json!(blocked as f64 / n as f64));
                }
                line.push(format!(
                    "{}: closest {:.2}, shadow {:.2}, camera {:.2} Mrays/s",
                    if packets { "packets of 8" } else { "one ray a query" },
                    rate(n, closest_s),
                    rate(n, shadow_s),
                    rate(camera.len(), camera_s)
                ));
            }
            let mut result = json!({
                "scene": scene.name, "backend": backend.name(), "triangles": scene.triangle_count(),
                "threads": rayon::current_num_threads(), "rays": args.rays, "camera_rays": camera.len(),
                "build_s": build_s,
            });
            if let Some(r) = result.as_object_mut() {
                r.extend(figures.clone());
            }
            if args.json {
                println!("{result}");
            } else {
                println!(
                    "{:<7} {} ({} triangles), {} threads: build {:.2} s, {:.0}% of closest rays hit, {:.0}% of shadow rays blocked\n  {}",
                    backend.name(),
                    scene.name,
                    scene.triangle_count(),
                    rayon::current_num_threads(),
                    build_s,
                    100.0 * figures["closest_hit_fraction"].as_f64().unwrap_or(0.0),
                    100.0 * figures["shadow_blocked_fraction"].as_f64().unwrap_or(0.0),
                    line.join("\n  ")
                );
            }
        }
        Ok(())
    })
}
