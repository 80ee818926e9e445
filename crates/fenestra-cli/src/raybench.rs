//! `fenestra raybench`: closest-hit and shadow-ray throughput of the ray-query backends on
//! incoherent rays (random origins in the scene bounds, uniform directions).

use crate::scene_arg;
use anyhow::{bail, Context, Result};
use clap::Args;
use fenestra_core::{warp, Ray, Sampler, Vec3};
use fenestra_scene::{Backend, Scene};
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
    let desc = scene_arg::load(&args.scene, args.scene_options)?.desc;
    pool.install(|| -> Result<()> {
        let backends = if args.bvh.is_empty() { Backend::available() } else { args.bvh.clone() };
        for backend in backends {
            let t0 = Instant::now();
            let scene = Scene::build(desc.clone(), backend).context("invalid scene")?;
            let build_s = t0.elapsed().as_secs_f64();
            let (closest, shadow) = make_rays(&scene, args.rays);
            let (hits, closest_s) =
                median_time(args.repeat, || closest.par_iter().filter(|r| scene.intersect(r, f32::INFINITY).is_some()).count());
            let (blocked, shadow_s) = median_time(args.repeat, || shadow.par_iter().filter(|(r, d)| scene.occluded(r, *d)).count());
            let n = args.rays as f64;
            let result = json!({
                "scene": scene.name, "backend": backend.name(), "triangles": scene.triangle_count(),
                "threads": rayon::current_num_threads(), "rays": args.rays, "build_s": build_s,
                "closest_mrays_per_s": n / closest_s / 1e6, "shadow_mrays_per_s": n / shadow_s / 1e6,
                "closest_hit_fraction": hits as f64 / n, "shadow_blocked_fraction": blocked as f64 / n,
            });
            if args.json {
                println!("{result}");
            } else {
                println!(
                    "{:<7} {} ({} triangles), {} threads: build {:.2} s, closest {:.2} Mrays/s ({:.0}% hit), shadow {:.2} Mrays/s ({:.0}% blocked)",
                    backend.name(),
                    scene.name,
                    scene.triangle_count(),
                    rayon::current_num_threads(),
                    build_s,
                    n / closest_s / 1e6,
                    100.0 * hits as f64 / n,
                    n / shadow_s / 1e6,
                    100.0 * blocked as f64 / n
                );
            }
        }
        Ok(())
    })
}
