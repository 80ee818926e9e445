//! Whether light paths pay (issue 66 item 4), measured before rendering: a small image of
//! the render's aspect is rendered through lp_lt's passes (camera paths joined to light
//! paths, from a stream of its own), and scored by its variance summed over the pixels
//! times the rays it traced, against the same figure for the camera paths alone, estimated
//! from the same render. Rays, not seconds: the score is the same on every machine, thread
//! count and part of a split render, so all of them decide alike.
//!
//! The camera paths alone are not rendered to measure them: where light paths pay, the
//! camera paths' estimate of that light is heavy-tailed (a glint found once in 10^5
//! samples), and its sample variance over a trial's samples is mostly far below its
//! variance (the dining room's measured 0.92x, 21.9x and 1.07x the joined render's
//! efficiency at 32768, 131072 and 524288 samples, where rendering measured 1.7x). Instead,
//! per pixel, the variance of the camera paths alone is the joined camera paths' variance
//! plus that of H, the light that MIS handed from them to the light paths, whose second
//! moment the light paths estimate where they sample it well (`Splats::handed_moment`):
//! E[H^2] = Integral f^2 w^2 / p_camera, taken over the light paths' samples as
//! s^2 r / M per splat (s the weighted splat, r the ratio of the densities, M the light
//! paths per pass). The covariance of H with the rest of the camera path's light is left
//! out.

use crate::light_passes::LightPasses;
use fenestra_render::film::Film;
use fenestra_render::{NoProgress, RenderControl, RenderScene, RenderSettings};
use std::time::Instant;

/// Samples per pixel of the trial's image (its variance is measured per pixel).
const SPP: u32 = 4;

/// The seed of the trial's samples (the render's own do not decide what it renders with).
const SEED: u64 = 0x7419_1a1;

/// The variance and the cost of a trial render.
#[derive(Clone, Copy, Debug)]
pub struct Score {
    /// The variance of the pixels' estimates, summed over the pixels and averaged over the
    /// channels.
    pub variance: f64,
    /// Rays traced.
    pub rays: u64,
}

impl Score {
    /// Variance times cost: the lower, the more efficient.
    fn work(&self) -> f64 {
        self.variance * self.rays as f64
    }
}

/// Both renders' scores.
#[derive(Clone, Copy, Debug)]
pub struct Trial {
    /// lp_hf's camera paths alone.
    pub without: Score,
    /// The camera paths and the light paths, joined.
    pub with: Score,
    /// Seconds both renders took.
    pub seconds: f64,
}

impl Trial {
    /// How many times as efficient the render with light paths is as the one without (1
    /// where neither has variance).
    pub fn gain(&self) -> f64 {
        let (without, with) = (self.without.work(), self.with.work());
        if with > 0.0 {
            without / with
        } else if without > 0.0 {
            f64::INFINITY
        } else {
            1.0
        }
    }
}

/// The trial image's size for `samples` camera samples of an image of `image` pixels (the
/// render's; 1920 x 1080 when unknown): the image itself where it has fewer pixels than that.
pub(crate) fn size(image: Option<(u32, u32)>, samples: u32) -> ((u32, u32), u32) {
    let (w, h) = image.unwrap_or((1920, 1080));
    let pixels = f64::from(w) * f64::from(h);
    let wanted = f64::from(samples / SPP).max(1.0);
    if pixels <= wanted {
        return ((w, h), samples.div_ceil(w * h).max(2));
    }
    let scale = (wanted / pixels).sqrt();
    let side = |n: u32| ((f64::from(n) * scale).round() as u32).max(1);
    ((side(w), side(h)), SPP)
}

/// Renders `passes` (camera paths joined to light paths) at `size` and `spp` (cancelled
/// with `control`, reporting nothing) and scores them with and without their light paths;
/// `None` when cancelled.
pub(crate) fn measure(
    mut passes: LightPasses,
    scene: &RenderScene,
    ((width, height), spp): ((u32, u32), u32),
    control: &RenderControl,
) -> Option<Trial> {
    let (started, quiet) = (
        Instant::now(),
        RenderControl::new(control.cancel, &NoProgress),
    );
    let settings = RenderSettings {
        spp,
        first_sample: 0,
        time_limit: None,
        seed: SEED,
    };
    let mut film = Film::new(width, height);
    let stats = passes.render(scene, &mut film, &settings, &quiet);
    if control.cancelled() {
        return None;
    }
    let channels = |v: [f64; 3]| (v[0] + v[1] + v[2]) / 3.0;
    let (mut camera, mut splats, mut handed_mean) = (0.0, 0.0, 0.0);
    for (i, p) in film.pixels.iter().enumerate() {
        let (mean, variance) = film.splat_estimate(i);
        camera += channels(p.variance_of_mean());
        splats += channels(variance);
        handed_mean += channels(mean.map(|m| m * m)) / f64::from(p.count.max(1));
    }
    let handed_square = passes.handed_moment / (film.light_paths.max(1) as f64) / f64::from(spp);
    let rays = stats.rays.total_rays();
    Some(Trial {
        without: Score {
            variance: camera + (handed_square - handed_mean).max(0.0),
            rays: rays - passes.light_rays.total_rays(),
        },
        with: Score {
            variance: camera + splats,
            rays,
        },
        seconds: started.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_trial_image_keeps_the_aspect_and_the_samples() {
        let ((w, h), spp) = size(Some((1920, 1080)), 32768);
        assert_eq!((w, h, spp), (121, 68, 4));
        let ((w, h), spp) = size(Some((32, 32)), 32768);
        assert_eq!((w, h, spp), (32, 32, 32));
        assert_eq!(size(None, 32768).0, (121, 68));
        assert_eq!(size(Some((1, 1)), 1), ((1, 1), 2));
    }

    #[test]
    fn gain_is_the_ratio_of_variance_times_rays() {
        let s = |variance, rays| Score { variance, rays };
        let trial = Trial {
            without: s(2.0, 100),
            with: s(0.5, 200),
            seconds: 0.0,
        };
        assert_eq!(trial.gain(), 2.0);
        let none = Trial {
            without: s(0.0, 1),
            with: s(0.0, 1),
            seconds: 0.0,
        };
        assert_eq!(none.gain(), 1.0);
    }
}
