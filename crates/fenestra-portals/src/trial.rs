//! Whether light paths pay (issue 66 item 4), measured before rendering: a small image of
//! the render's aspect is rendered through lp_lt's passes twice, from the same samples (a
//! stream of their own), the camera paths joined to light paths and alone, and each scored
//! by its variance summed over the pixels times the rays it traced. Rays, not seconds: the
//! score is the same on every machine, thread count and part of a split render, so all of
//! them decide alike.
//!
//! The camera paths' variance alone has two estimates, and the trial takes the larger.
//! Their own render's sample variance is mostly far below their variance where light paths
//! pay most: their estimate of the glints is heavy-tailed (one found in 10^5 samples), and
//! on the dining room it measured light paths at 0.92x, 21.9x and 1.07x at 32768, 131072
//! and 524288 samples, where rendering measured 1.7x. The other is taken from the joined
//! render: a vertex's contribution c that the camera paths keep at weight 1 - w adds
//! c^2 w (2 - w) to their second moment when they carry all of it, and the light paths
//! estimate its mean where they sample it well (`Splats::handed_moment`); it leaves out the
//! covariances between the shared light and the camera path's light elsewhere, which on a
//! diffuse room lit through its window (the sun's bounce off the sunlit floor) put it 15%
//! low, where the render's own estimate is close.

use crate::light_passes::LightPasses;
use fenestra_render::film::Film;
use fenestra_render::{NoProgress, RenderControl, RenderScene, RenderSettings};

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

/// Renders `passes` at `size` and `spp` from the trial's samples (cancelled with
/// `control`, reporting nothing): the film and the rays traced, or `None` when cancelled.
fn render(
    passes: &mut LightPasses,
    scene: &RenderScene,
    ((width, height), spp): ((u32, u32), u32),
    control: &RenderControl,
) -> Option<(Film, u64)> {
    let quiet = RenderControl::new(control.cancel, &NoProgress);
    let settings = RenderSettings {
        spp,
        first_sample: 0,
        time_limit: None,
        seed: SEED,
    };
    let mut film = Film::new(width, height);
    let stats = passes.render(scene, &mut film, &settings, &quiet);
    (!control.cancelled()).then(|| (film, stats.rays.total_rays()))
}

/// A film's channels averaged.
fn channels(v: [f64; 3]) -> f64 {
    (v[0] + v[1] + v[2]) / 3.0
}

/// The score of a trial render of camera paths joined to light paths, and the variance of
/// the camera paths alone estimated from it.
pub(crate) struct Joined {
    with: Score,
    estimated: f64,
}

/// Renders `passes` (camera paths joined to light paths) at `size` (cancelled with
/// `control`) and scores them; `None` when cancelled.
pub(crate) fn joined(
    mut passes: LightPasses,
    scene: &RenderScene,
    size: ((u32, u32), u32),
    control: &RenderControl,
) -> Option<Joined> {
    let (film, rays) = render(&mut passes, scene, size, control)?;
    // Per pixel and channel, variances of the mean: the joined camera paths' (V), the
    // light paths' (S), and for the camera paths alone V + (E[c^2 w (2 - w)] - h^2) / n,
    // h the light paths' mean and n the samples (the shared light's covariance with the
    // rest of its camera path left out).
    let (mut camera, mut splats, mut squared) = (0.0, 0.0, 0.0);
    for (i, p) in film.pixels.iter().enumerate() {
        let (h, variance) = film.splat_estimate(i);
        camera += channels(p.variance_of_mean());
        splats += channels(variance);
        squared += channels(h.map(|h| h * h)) / f64::from(p.count.max(1));
    }
    let spp = f64::from(size.1);
    let added = passes.handed_moment / (film.light_paths.max(1) as f64) / spp;
    Some(Joined {
        with: Score {
            variance: camera + splats,
            rays,
        },
        estimated: camera + (added - squared).max(0.0),
    })
}

/// Renders `passes` (camera paths alone) at `size` (cancelled with `control`) and scores
/// them; `None` when cancelled.
pub(crate) fn alone(
    mut passes: LightPasses,
    scene: &RenderScene,
    size: ((u32, u32), u32),
    control: &RenderControl,
) -> Option<Score> {
    let (film, rays) = render(&mut passes, scene, size, control)?;
    let variance = film.variance_image();
    let variance = (variance.pixels.iter())
        .map(|p| channels([p.r, p.g, p.b].map(f64::from)))
        .sum();
    Some(Score { variance, rays })
}

impl Trial {
    /// The trial of `joined` and `alone` that took `seconds`: the variance alone is the
    /// larger of its two estimates, its own render's (low where its light is heavy-tailed)
    /// and the one taken from the joined render (low by the covariances it leaves out).
    pub(crate) fn of(joined: Joined, alone: Score, seconds: f64) -> Trial {
        Trial {
            without: Score {
                variance: f64::max(joined.estimated, alone.variance),
                rays: alone.rays,
            },
            with: joined.with,
            seconds,
        }
    }
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
