//! Integrators render a whole image; [`render_progressive`] turns a per-path estimator into a
//! parallel, progressive, interruptible one whose result does not depend on the thread count.

mod path;

pub use path::{NextEvent, PathTracer};

use crate::film::Film;
use crate::portal::Portals;
use crate::stats::{RayCounters, RenderStats};
use crate::RenderScene;
use fenestra_core::mis::MisHeuristic;
use fenestra_core::{Rgb, Sampler, Vec2};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

#[derive(Clone, Debug)]
pub struct RenderSettings {
    /// Samples per pixel (an upper bound when `time_limit` is set).
    pub spp: u32,
    /// Stop after about this many seconds, at a whole number of samples per pixel.
    pub time_limit: Option<f64>,
    pub seed: u64,
}

/// Receives progress: `start` once with the total work (samples, if known), then `advance`.
pub trait Progress: Sync {
    fn start(&self, _total: Option<u64>) {}
    fn advance(&self, _samples: u64) {}
}

pub struct NoProgress;
impl Progress for NoProgress {}

/// Called after every completed pass with the film and the seconds spent so far; returns
/// whether to go on (a measurement can stop a render once it reaches a target error).
pub type PassHook<'a> = &'a (dyn Fn(&Film, f64) -> bool + Sync);

/// Progress reporting, cancellation (Ctrl-C) and a per-pass hook for a render.
pub struct RenderControl<'a> {
    pub cancel: &'a AtomicBool,
    pub progress: &'a dyn Progress,
    pub on_pass: Option<PassHook<'a>>,
}

impl<'a> RenderControl<'a> {
    pub fn new(cancel: &'a AtomicBool, progress: &'a dyn Progress) -> Self {
        RenderControl {
            cancel,
            progress,
            on_pass: None,
        }
    }
}

pub trait Integrator: Sync {
    fn name(&self) -> String;
    fn max_depth(&self) -> u32;
    fn render(
        &self,
        scene: &RenderScene,
        film: &mut Film,
        settings: &RenderSettings,
        control: &RenderControl,
    ) -> RenderStats;
}

/// Options shared by the path-tracing integrators.
#[derive(Clone, Debug)]
pub struct IntegratorOptions {
    /// Maximum path length in segments (2 = direct light only).
    pub max_depth: u32,
    pub mis: MisHeuristic,
    /// Path length from which Russian roulette may end a path.
    pub rr_depth: u32,
}

impl Default for IntegratorOptions {
    fn default() -> Self {
        IntegratorOptions {
            max_depth: 8,
            mis: MisHeuristic::Power { beta: 2.0 },
            rr_depth: 3,
        }
    }
}

/// The integrators known by name.
pub const INTEGRATORS: &[(&str, &str)] = &[
    ("hf", "BSDF sampling only (hemispherical formulation)"),
    (
        "af_hf",
        "next-event estimation on emitters and BSDF sampling combined by MIS",
    ),
    (
        "lp_hf",
        "light-portal sampling and BSDF sampling combined by MIS (needs portals)",
    ),
];

/// The integrator called `name`; `portals` are used by lp_hf (which refuses an empty set),
/// mixed with light sampling with probability `light_mix`.
pub fn by_name(
    name: &str,
    options: IntegratorOptions,
    portals: Portals,
    light_mix: f32,
) -> Result<Box<dyn Integrator>, String> {
    match name {
        "hf" => Ok(Box::new(PathTracer::new(false, options))),
        "af_hf" => Ok(Box::new(PathTracer::new(true, options))),
        "lp_hf" if portals.is_empty() => {
            Err("lp_hf needs light portals and the scene has none".into())
        }
        "lp_hf" => Ok(Box::new(PathTracer::with_portals(
            portals, light_mix, options,
        ))),
        _ => {
            let names: Vec<&str> = INTEGRATORS.iter().map(|i| i.0).collect();
            Err(format!(
                "unknown integrator '{name}' (available: {})",
                names.join(", ")
            ))
        }
    }
}

/// One path sample: the radiance carried along `ray` into the camera.
pub trait PathEstimator: Sync {
    fn li(
        &self,
        scene: &RenderScene,
        ray: fenestra_core::Ray,
        sampler: &mut Sampler,
        rays: &mut RayCounters,
    ) -> Rgb;
}

/// Largest number of samples per pixel added in one pass (keeps Ctrl-C and time limits prompt).
const MAX_PASS: u32 = 32;

/// Renders in passes of growing size over all rows in parallel. Sample `i` of pixel `p`
/// always uses the stream (seed, p, i) and is added in index order, so the image is the same
/// bit for bit whatever the number of threads.
pub fn render_progressive(
    name: &str,
    max_depth: u32,
    estimator: &impl PathEstimator,
    scene: &RenderScene,
    film: &mut Film,
    settings: &RenderSettings,
    control: &RenderControl,
) -> RenderStats {
    let start = Instant::now();
    let (width, height) = (film.width, film.height);
    let pixels = width as u64 * height as u64;
    control.progress.start(
        settings
            .time_limit
            .is_none()
            .then_some(pixels * settings.spp as u64),
    );
    let mut rays = RayCounters::default();
    let mut done = 0u32;
    let mut pass = 1u32;
    let mut interrupted = false;
    while done < settings.spp {
        let mut n = pass.min(settings.spp - done);
        if let (Some(limit), true) = (settings.time_limit, done > 0) {
            let elapsed = start.elapsed().as_secs_f64();
            let per_sample = elapsed / done as f64;
            n = n.min(((limit - elapsed) / per_sample).floor().max(0.0) as u32);
            if n == 0 {
                break;
            }
        }
        let first = done;
        rays += film
            .pixels
            .par_chunks_mut(width as usize)
            .enumerate()
            .map(|(y, row)| {
                let mut counters = RayCounters::default();
                if control.cancel.load(Ordering::Relaxed) {
                    return counters;
                }
                for (x, pixel) in row.iter_mut().enumerate() {
                    let index = y as u64 * width as u64 + x as u64;
                    for s in first..first + n {
                        let mut sampler = Sampler::new(settings.seed, index, s);
                        let film_pos = Vec2::new(x as f32, y as f32) + sampler.next_2d();
                        let ray = scene.scene.camera.generate_ray(film_pos, width, height);
                        counters.camera += 1;
                        let l = estimator.li(scene, ray, &mut sampler, &mut counters);
                        if l.is_finite() {
                            pixel.add(l);
                        } else {
                            counters.dropped += 1;
                        }
                    }
                }
                control.progress.advance(n as u64 * width as u64);
                counters
            })
            .reduce(RayCounters::default, |mut a, b| {
                a += b;
                a
            });
        if control.cancel.load(Ordering::Relaxed) {
            interrupted = true;
            break;
        }
        done += n;
        pass = (pass * 2).min(MAX_PASS);
        if let Some(hook) = control.on_pass {
            if !hook(film, start.elapsed().as_secs_f64()) {
                break;
            }
        }
    }
    let time_s = start.elapsed().as_secs_f64();
    let (spp, spp_max) = film.sample_count_range();
    RenderStats {
        scene: scene.scene.name.clone(),
        integrator: name.to_string(),
        backend: scene.scene.backend.name().to_string(),
        width,
        height,
        spp,
        spp_max,
        max_depth,
        seed: settings.seed,
        threads: rayon::current_num_threads(),
        time_s,
        rays,
        total_rays: rays.total_rays(),
        mrays_per_s: rays.total_rays() as f64 / time_s.max(1e-9) / 1e6,
        shadow_rays_per_pixel: rays.shadow as f64 / pixels.max(1) as f64,
        interrupted,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::LightSelection;
    use fenestra_scene::{builtin, Backend, Scene};

    /// Returns NaN, +inf or 1 depending on the sample's first random number.
    struct Faulty;
    impl PathEstimator for Faulty {
        fn li(
            &self,
            _: &RenderScene,
            _: fenestra_core::Ray,
            sampler: &mut Sampler,
            _: &mut RayCounters,
        ) -> Rgb {
            match (sampler.next_1d() * 4.0) as u32 {
                0 => Rgb::new(f32::NAN, 0.0, 0.0),
                1 => Rgb::splat(f32::INFINITY),
                _ => Rgb::ONE,
            }
        }
    }

    #[test]
    fn non_finite_samples_are_dropped_and_counted() {
        let scene = Scene::build(builtin::load("box-hole").expect("builtin"), Backend::Obvhs)
            .expect("scene");
        let scene = RenderScene::new(scene, LightSelection::Power);
        let mut film = Film::new(8, 8);
        let cancel = AtomicBool::new(false);
        let control = RenderControl::new(&cancel, &NoProgress);
        let settings = RenderSettings {
            spp: 16,
            time_limit: None,
            seed: 3,
        };
        let stats =
            render_progressive("faulty", 2, &Faulty, &scene, &mut film, &settings, &control);
        let kept: u64 = film.pixels.iter().map(|p| p.count as u64).sum();
        assert!(stats.rays.dropped > 0);
        assert_eq!(kept + stats.rays.dropped, 8 * 8 * 16);
        assert!(
            film.image().pixels.iter().all(|p| *p == Rgb::ONE),
            "only finite samples reach the film"
        );
    }
}
