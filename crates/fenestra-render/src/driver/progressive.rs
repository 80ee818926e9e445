//! The per-path driver: an estimator that maps a camera ray to radiance is rendered in passes
//! of 1, 2, 4, ... up to 32 samples per pixel until the sample count, or the time limit (of
//! rendering, preparation not included), is reached (small first passes make Ctrl-C, time
//! limits and convergence curves prompt).

use super::passes::{render_passes, PassEstimator, PassInfo, PixelState};
use super::SampleContext;
use crate::control::RenderControl;
use crate::film::Film;
use crate::render_scene::RenderScene;
use crate::settings::RenderSettings;
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_core::{Ray, Rgb, Sampler};

/// One path sample: the radiance carried along a camera ray.
pub trait PathEstimator: Sync {
    /// Radiance arriving at the camera along `ray`, for the sample `ctx`.
    fn li(
        &self,
        scene: &RenderScene,
        ray: Ray,
        sampler: &mut Sampler,
        ctx: &SampleContext,
        rays: &mut RayCounters,
    ) -> Rgb;
}

/// Largest number of samples per pixel added in one pass.
const MAX_PASS: u32 = 32;

/// Renders `estimator` with `settings.spp` samples per pixel, or as many as fit in the time
/// limit (a whole number per pixel).
pub fn render_progressive(
    estimator: &impl PathEstimator,
    scene: &RenderScene,
    film: &mut Film,
    settings: &RenderSettings,
    control: &RenderControl,
) -> RenderStats {
    let mut schedule = Schedule {
        estimator,
        spp: settings.spp,
        time_limit: settings.time_limit,
        done: 0,
        size: 1,
        current: 0,
    };
    render_passes(&mut schedule, scene, film, settings, control)
}

/// The pass schedule: every pixel takes `current` samples in a pass.
struct Schedule<'a, E> {
    estimator: &'a E,
    spp: u32,
    time_limit: Option<f64>,
    /// Samples per pixel of the completed passes.
    done: u32,
    /// Size of the next pass before the sample count and time limit cut it.
    size: u32,
    current: u32,
}

impl<E: PathEstimator> PassEstimator for Schedule<'_, E> {
    type BlockStats = ();

    fn expected_samples(&self, pixels: u64) -> Option<u64> {
        self.time_limit
            .is_none()
            .then_some(pixels * self.spp as u64)
    }

    fn begin_pass(&mut self, pass: &PassInfo) -> bool {
        if self.done >= self.spp {
            return false;
        }
        let mut n = self.size.min(self.spp - self.done);
        // The time limit counts rendering: preparation (portal estimation, caches) comes on
        // top, and the statistics' total time shows it.
        if let (Some(limit), true) = (self.time_limit, self.done > 0) {
            let per_sample = pass.render_s / self.done as f64;
            n = n.min(((limit - pass.render_s) / per_sample).floor().max(0.0) as u32);
        }
        self.current = n;
        n > 0
    }

    fn block_stats(&self, _: u32, _: u32) {}

    fn samples(&self, _: &PixelState) -> u32 {
        self.current
    }

    fn sample(
        &self,
        scene: &RenderScene,
        ctx: &SampleContext,
        sampler: &mut Sampler,
        _: &mut (),
        rays: &mut RayCounters,
    ) -> Rgb {
        let ray = ctx.camera_ray(scene, sampler, rays);
        self.estimator.li(scene, ray, sampler, ctx, rays)
    }

    fn end_pass(&mut self, _: &RenderScene, _: &Film, _: Vec<()>) -> bool {
        self.done += self.current;
        self.size = (self.size * 2).min(MAX_PASS);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::NoProgress;
    use fenestra_builtin as builtin;
    use fenestra_scene::{Backend, Scene};
    use std::sync::atomic::AtomicBool;

    /// Returns NaN, +inf or 1 depending on the sample's first random number.
    struct Faulty;
    impl PathEstimator for Faulty {
        fn li(
            &self,
            _: &RenderScene,
            _: Ray,
            sampler: &mut Sampler,
            _: &SampleContext,
            _: &mut RayCounters,
        ) -> Rgb {
            match (sampler.next_1d() * 4.0) as u32 {
                0 => Rgb::new(f32::NAN, 0.0, 0.0),
                1 => Rgb::splat(f32::INFINITY),
                _ => Rgb::ONE,
            }
        }
    }

    fn render(settings: &RenderSettings, size: u32) -> (Film, RenderStats) {
        let scene = Scene::build(builtin::load("box-hole").expect("builtin"), Backend::Obvhs)
            .expect("scene");
        let scene = RenderScene::new(scene);
        let mut film = Film::new(size, size);
        let cancel = AtomicBool::new(false);
        let control = RenderControl::new(&cancel, &NoProgress);
        let stats = render_progressive(&Faulty, &scene, &mut film, settings, &control);
        (film, stats)
    }

    #[test]
    fn non_finite_samples_are_dropped_and_counted() {
        let settings = RenderSettings {
            first_sample: 0,
            spp: 16,
            time_limit: None,
            seed: 3,
        };
        // 12 is not a multiple of the 8-pixel blocks: partial blocks at the edges.
        let (film, stats) = render(&settings, 12);
        let kept: u64 = film.pixels.iter().map(|p| p.count as u64).sum();
        assert!(stats.rays.dropped > 0);
        assert_eq!(kept + stats.rays.dropped, 12 * 12 * 16);
        assert_eq!(stats.rays.camera, 12 * 12 * 16);
        // Passes of 1, 2, 4, 8 and the remaining 1.
        assert_eq!(stats.passes, 5);
        assert!(
            film.image().pixels.iter().all(|p| *p == Rgb::ONE),
            "only finite samples reach the film"
        );
    }
}
