//! The film: per-pixel sums of samples and of their squares (box filter over the pixel), so
//! that the image and the variance of each pixel's mean come out of one render.
//!
//! The sums are exact: every sample is held in fixed point with 64 fractional bits (every
//! f32 of magnitude at least 2^-41 exactly, smaller ones to within 2^-65) and summed in
//! 128-bit integers. Integer addition does not depend on order, so pieces of a render (sample
//! ranges, tiles) rendered apart and merged give the very sums, and so the very image, that
//! one render makes.

use crate::features::FeaturePixel;
use crate::splat::Splats;
use fenestra_core::image::{Estimate, Image};
use fenestra_core::Rgb;
use glam::Mat3;

/// Scale of the fixed-point sums: 2^64 units per unit of radiance.
pub(crate) const ONE: f64 = 18_446_744_073_709_551_616.0;

/// Largest magnitude a sample may have in any channel: 2^31, so that 2^32 samples of it sum
/// within the 128-bit accumulators. Larger samples are dropped and counted, as non-finite
/// ones are.
pub const MAX_SAMPLE: f32 = 2_147_483_648.0;

/// `x` in units of 2^-64, rounded to nearest (ties away from zero), for |x| < 2^63: read off
/// the float's bits with integer shifts, several times faster than a float-to-i128 cast.
fn fixed(x: f64) -> i128 {
    let bits = x.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as i32;
    let fraction = (bits & ((1 << 52) - 1)) as i128;
    let mantissa = if exponent == 0 {
        fraction
    } else {
        fraction | 1 << 52
    };
    // x = mantissa * 2^(e - 1075) with e the exponent (1 for subnormals): in units of 2^-64,
    // mantissa * 2^(e - 1011).
    let shift = exponent.max(1) - 1011;
    let q = if shift >= 0 {
        mantissa << shift
    } else if shift > -54 {
        (mantissa + (1 << (-shift - 1))) >> -shift
    } else {
        0
    };
    if bits >> 63 == 1 {
        -q
    } else {
        q
    }
}

/// One pixel's accumulators.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Pixel {
    /// Sum of the samples, per channel, in units of 2^-64.
    pub sum: [i128; 3],
    /// Sum of their squares, per channel, in units of 2^-64; it saturates (at about
    /// 1.8e19), which makes the pixel's variance infinite rather than wrong.
    pub sum_sq: [u128; 3],
    /// Samples added.
    pub count: u32,
}

impl Pixel {
    /// Whether the film takes `c`: finite, and within [`MAX_SAMPLE`] in every channel.
    pub fn accepts(c: Rgb) -> bool {
        c.to_array().iter().all(|v| v.abs() < MAX_SAMPLE)
    }

    /// Adds one sample, which the film must accept ([`Pixel::accepts`]).
    pub fn add(&mut self, c: Rgb) {
        debug_assert!(Pixel::accepts(c));
        for (i, v) in c.to_array().into_iter().enumerate() {
            self.add_value(i, v as f64);
        }
        self.count += 1;
    }

    fn add_value(&mut self, channel: usize, v: f64) {
        // An f32's square is exact in f64.
        self.sum[channel] += fixed(v);
        self.sum_sq[channel] = self.sum_sq[channel].saturating_add(fixed(v * v) as u128);
    }

    /// Sets the pixel to an estimate `mean` whose mean has the variance `variance` (per
    /// channel), for estimators that combine their samples otherwise than by averaging
    /// (seed 004's inverse-variance weighting of passes): stored as the two samples
    /// mean +- sqrt(variance), whose mean and variance of the mean are these (to within the
    /// fixed point's resolution).
    pub fn set_estimate(&mut self, mean: [f64; 3], variance: [f64; 3]) {
        *self = Pixel::default();
        for sign in [1.0, -1.0] {
            for i in 0..3 {
                let v = mean[i] + sign * variance[i].max(0.0).sqrt();
                self.add_value(i, v.clamp(-f64::from(MAX_SAMPLE), f64::from(MAX_SAMPLE)));
            }
            self.count += 1;
        }
    }

    /// Adds the samples of `other`, taken apart (another sample range of the same pixel);
    /// false, and the pixel unchanged, if the count or a sum would overflow.
    pub fn checked_merge(&mut self, other: &Pixel) -> bool {
        let Some(count) = self.count.checked_add(other.count) else {
            return false;
        };
        let mut sum = self.sum;
        for (s, o) in sum.iter_mut().zip(other.sum) {
            match s.checked_add(o) {
                Some(v) => *s = v,
                None => return false,
            }
        }
        for i in 0..3 {
            self.sum_sq[i] = self.sum_sq[i].saturating_add(other.sum_sq[i]);
        }
        (self.sum, self.count) = (sum, count);
        true
    }

    /// The sample mean, per channel.
    pub fn mean(&self) -> [f64; 3] {
        let n = self.count.max(1) as f64;
        self.sum.map(|s| s as f64 / ONE / n)
    }

    /// Variance of the pixel mean (sample variance / n), per channel: infinite when the sum
    /// of squares saturated.
    pub fn variance_of_mean(&self) -> [f64; 3] {
        let n = self.count as f64;
        if n < 2.0 {
            return [0.0; 3];
        }
        std::array::from_fn(|i| {
            if self.sum_sq[i] == u128::MAX {
                return f64::INFINITY;
            }
            let mean = self.sum[i] as f64 / ONE / n;
            let mean_sq = self.sum_sq[i] as f64 / ONE / n;
            ((mean_sq - mean * mean) * n / (n - 1.0)).max(0.0) / n
        })
    }
}

/// The part of the image a film holds: the rectangle [x0, x1) x [y0, y1) of a
/// `full_width` x `full_height` image (all of it unless the render is cropped).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Window {
    /// Width of the whole image.
    pub full_width: u32,
    /// Height of the whole image.
    pub full_height: u32,
    /// First column.
    pub x0: u32,
    /// First row (0 at the top).
    pub y0: u32,
    /// One past the last column.
    pub x1: u32,
    /// One past the last row.
    pub y1: u32,
}

impl Window {
    /// The whole of a `width` x `height` image.
    pub fn full(width: u32, height: u32) -> Self {
        Window {
            full_width: width,
            full_height: height,
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    /// Width of the window.
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    /// Height of the window.
    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    /// Whether it is the whole image.
    pub fn is_full(&self) -> bool {
        *self == Window::full(self.full_width, self.full_height)
    }

    /// Row-major index within the window of the image's pixel (x, y), if the window holds it.
    pub fn index(&self, (x, y): (u32, u32)) -> Option<usize> {
        (x >= self.x0 && x < self.x1 && y >= self.y0 && y < self.y1)
            .then(|| ((y - self.y0) as usize) * self.width() as usize + (x - self.x0) as usize)
    }

    /// Whether the two windows share a pixel.
    pub fn overlaps(&self, other: &Window) -> bool {
        self.x0 < other.x1 && other.x0 < self.x1 && self.y0 < other.y1 && other.y0 < self.y1
    }
}

impl std::fmt::Display for Window {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "{},{},{},{}", self.x0, self.y0, self.x1, self.y1)
    }
}

/// The image being rendered: one [`Pixel`] of accumulators per pixel of its window,
/// row-major.
#[derive(Clone, Debug)]
pub struct Film {
    /// Width in pixels (of the window).
    pub width: u32,
    /// Height in pixels (of the window).
    pub height: u32,
    /// Which part of the image it holds.
    pub window: Window,
    /// Row-major, top row first.
    pub pixels: Vec<Pixel>,
    /// Light tracing's sums per pixel (sums and squares of the splats that landed there; the
    /// count is unused), row-major; empty until a light path is traced.
    pub splats: Vec<Pixel>,
    /// Light paths traced into the film: each pixel's light-tracing estimate is its splat sum
    /// over this number.
    pub light_paths: u64,
    /// Denoising features per pixel (albedo and normal sums), row-major; empty when the
    /// render does not take them ([`Film::with_features`]).
    pub features: Vec<FeaturePixel>,
}

impl Film {
    /// An empty film for a whole `width` x `height` image.
    pub fn new(width: u32, height: u32) -> Self {
        Film::cropped(Window::full(width, height))
    }

    /// An empty film for a window of an image.
    pub fn cropped(window: Window) -> Self {
        let (width, height) = (window.width(), window.height());
        Film {
            width,
            height,
            window,
            pixels: vec![Pixel::default(); width as usize * height as usize],
            splats: Vec::new(),
            light_paths: 0,
            features: Vec::new(),
        }
    }

    /// The film, taking denoising features beside its samples.
    pub fn with_features(mut self) -> Self {
        self.features = vec![FeaturePixel::default(); self.pixels.len()];
        self
    }

    /// Whether the film takes denoising features.
    pub fn takes_features(&self) -> bool {
        !self.features.is_empty()
    }

    /// The denoising features as images, (albedo, normal), if the film takes them.
    pub fn feature_images(&self) -> Option<(Image, Image)> {
        if !self.takes_features() {
            return None;
        }
        let (w, h) = (self.width as usize, self.height as usize);
        let (mut albedo, mut normal) = (Image::new(w, h), Image::new(w, h));
        for (i, f) in self.features.iter().enumerate() {
            albedo.pixels[i] = f.albedo();
            let n = f.normal();
            normal.pixels[i] = Rgb::new(n.x, n.y, n.z);
        }
        Some((albedo, normal))
    }

    /// Adds a block's splats of a pass (those in the film's window; the rest belong to other
    /// pieces of the image), seen by the sensor `response` as camera samples are; returns how
    /// many were dropped as the film drops samples it does not take.
    pub fn add_splats(&mut self, splats: &Splats, response: Option<Mat3>) -> u64 {
        if self.splats.is_empty() {
            self.splats = vec![Pixel::default(); self.pixels.len()];
        }
        self.light_paths += splats.paths;
        let w = self.window;
        let mut dropped = 0;
        for s in &splats.entries {
            if !(w.x0..w.x1).contains(&s.x) || !(w.y0..w.y1).contains(&s.y) {
                continue;
            }
            let v = response.map_or(s.value, |m| s.value.transformed(m));
            if !Pixel::accepts(v) {
                dropped += 1;
                continue;
            }
            let i = (s.y - w.y0) as usize * self.width as usize + (s.x - w.x0) as usize;
            self.splats[i].add(v);
        }
        dropped
    }

    /// Each pixel's light-tracing estimate and the variance of that estimate, per channel:
    /// the mean over every light path of what it brought to the pixel (most bring nothing).
    /// A path that splats into one pixel twice counts as two paths' worth in the variance,
    /// which a path's few vertices seldom do.
    pub fn splat_estimate(&self, i: usize) -> ([f64; 3], [f64; 3]) {
        let (Some(p), n) = (self.splats.get(i), self.light_paths as f64) else {
            return ([0.0; 3], [0.0; 3]);
        };
        let mut mean = [0.0; 3];
        let mut variance = [0.0; 3];
        for c in 0..3 {
            let m = p.sum[c] as f64 / ONE / n;
            let sq = p.sum_sq[c] as f64 / ONE / n;
            mean[c] = m;
            variance[c] = if p.sum_sq[c] == u128::MAX {
                f64::INFINITY
            } else {
                ((sq - m * m) / (n - 1.0).max(1.0)).max(0.0)
            };
        }
        (mean, variance)
    }

    /// The share of the image's light (its luminance summed over the pixels) that light
    /// paths brought, or `None` when none were traced or the image is black.
    pub fn light_path_share(&self) -> Option<f64> {
        self.light_path_part(Pixel::mean, 0)
    }

    /// The share of the image's variance (the luminance of each pixel's variance of the
    /// mean, summed over the pixels) that the light paths' estimates hold, or `None` when
    /// none were traced or nothing varies.
    pub fn light_path_variance_share(&self) -> Option<f64> {
        self.light_path_part(Pixel::variance_of_mean, 1)
    }

    /// The light paths' part of the camera samples' figure `camera` plus light tracing's
    /// (`splat` picks the estimate or its variance), by luminance summed over the pixels.
    fn light_path_part(&self, camera: impl Fn(&Pixel) -> [f64; 3], splat: usize) -> Option<f64> {
        if self.light_paths == 0 {
            return None;
        }
        let luminance = |v: [f64; 3]| f64::from(rgb(v).luminance());
        let (mut splatted, mut all) = (0.0f64, 0.0f64);
        for (i, p) in self.pixels.iter().enumerate() {
            let e = self.splat_estimate(i);
            let s = luminance([e.0, e.1][splat]);
            splatted += s;
            all += s + luminance(camera(p));
        }
        (all > 0.0).then(|| splatted / all)
    }

    /// What the light paths brought each pixel and the variance of that estimate, as
    /// images, or `None` when none were traced.
    pub fn light_path_images(&self) -> Option<(Image, Image)> {
        if self.light_paths == 0 {
            return None;
        }
        let (w, h) = (self.width as usize, self.height as usize);
        let (mut light, mut variance) = (Image::new(w, h), Image::new(w, h));
        for i in 0..self.pixels.len() {
            let (m, v) = self.splat_estimate(i);
            light.pixels[i] = rgb(m);
            variance.pixels[i] = rgb(v);
        }
        Some((light, variance))
    }

    /// Per pixel, the camera samples' figure `f` plus light tracing's (`splat` picks the
    /// estimate or its variance).
    fn to_image(&self, f: impl Fn(&Pixel) -> [f64; 3], splat: usize) -> Image {
        let mut img = Image::new(self.width as usize, self.height as usize);
        for (i, (dst, p)) in img.pixels.iter_mut().zip(&self.pixels).enumerate() {
            let mut v = f(p);
            if self.light_paths > 0 {
                let s = self.splat_estimate(i);
                let s = [s.0, s.1][splat];
                v = std::array::from_fn(|c| v[c] + s[c]);
            }
            *dst = rgb(v);
        }
        img
    }

    /// The rendered image: each pixel's sample mean, plus what light paths brought it.
    pub fn image(&self) -> Image {
        self.to_image(Pixel::mean, 0)
    }

    /// The image and its per-pixel variance of the mean.
    pub fn estimate(&self) -> Estimate {
        Estimate {
            mean: self.image(),
            variance: self.variance_image(),
        }
    }

    /// Per-pixel variance of the mean (of the camera samples' and the light paths'
    /// estimates, which are independent).
    pub fn variance_image(&self) -> Image {
        self.to_image(Pixel::variance_of_mean, 1)
    }

    /// (smallest, largest) samples taken by any pixel.
    pub fn sample_count_range(&self) -> (u32, u32) {
        let min = self.pixels.iter().map(|p| p.count).min().unwrap_or(0);
        let max = self.pixels.iter().map(|p| p.count).max().unwrap_or(0);
        (min, max)
    }
}

/// A colour of f64 channels as f32.
fn rgb(v: [f64; 3]) -> Rgb {
    Rgb::new(v[0] as f32, v[1] as f32, v[2] as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples() -> Vec<Rgb> {
        let mut rng = fenestra_core::rng::Rng::new(7);
        (0..1000)
            .map(|i| {
                let scale = [1e-7, 1.0, 3e4][i % 3];
                Rgb::new(
                    rng.next_f32() * scale,
                    rng.next_f32(),
                    -rng.next_f32() * 0.5,
                )
            })
            .collect()
    }

    #[test]
    fn fixed_point_is_the_value_rounded_to_units_of_2_to_the_minus_64() {
        let mut rng = fenestra_core::rng::Rng::new(3);
        for _ in 0..100_000 {
            let x = (rng.next_f64() - 0.5) * 2f64.powi(rng.below(100) as i32 - 70);
            assert_eq!(fixed(x), (x * ONE).round() as i128, "{x}");
        }
        for x in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            2f64.powi(-65),
            2f64.powi(62),
            f64::MIN_POSITIVE,
        ] {
            assert_eq!(fixed(x), (x * ONE).round() as i128, "{x}");
        }
    }

    #[test]
    fn sums_do_not_depend_on_order_or_on_splitting() {
        let s = samples();
        let mut whole = Pixel::default();
        s.iter().for_each(|&c| whole.add(c));
        let mut backwards = Pixel::default();
        s.iter().rev().for_each(|&c| backwards.add(c));
        assert_eq!(whole, backwards);
        let (mut a, mut b) = (Pixel::default(), Pixel::default());
        s[..377].iter().for_each(|&c| a.add(c));
        s[377..].iter().for_each(|&c| b.add(c));
        assert!(b.checked_merge(&a));
        assert_eq!(whole, b);
        // An f64 running sum would differ in its last bits between these orders.
        let exact: f64 = s.iter().map(|c| c.r as f64).sum::<f64>() / s.len() as f64;
        assert!((whole.mean()[0] - exact).abs() <= 1e-12 * exact.abs());
    }

    #[test]
    fn mean_and_variance_match_the_textbook_formulas() {
        let s = samples();
        let mut p = Pixel::default();
        s.iter().for_each(|&c| p.add(c));
        let n = s.len() as f64;
        let g: Vec<f64> = s.iter().map(|c| c.g as f64).collect();
        let mean = g.iter().sum::<f64>() / n;
        let var = g.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0) / n;
        assert!((p.mean()[1] - mean).abs() < 1e-15);
        assert!((p.variance_of_mean()[1] / var - 1.0).abs() < 1e-9);
    }

    #[test]
    fn splats_add_to_the_camera_estimate_over_the_light_paths_in_the_window() {
        use crate::splat::Splats;
        let mut film = Film::cropped(Window {
            full_width: 8,
            full_height: 8,
            x0: 2,
            y0: 2,
            x1: 6,
            y1: 6,
        });
        film.pixels[0].add(Rgb::splat(1.0));
        let mut a = Splats::default();
        (0..3).for_each(|_| a.count_path());
        a.add(2, 2, Rgb::new(6.0, 0.0, 3.0));
        a.add(0, 0, Rgb::splat(100.0)); // outside the window: another piece's
        let mut b = Splats::default();
        b.count_path();
        b.add(2, 2, Rgb::new(2.0, 0.0, 1.0));
        b.add(5, 5, Rgb::new(f32::NAN, 0.0, 0.0));
        assert_eq!(film.add_splats(&a, None), 0);
        assert_eq!(film.add_splats(&b, None), 1, "the NaN is dropped");
        assert_eq!(film.light_paths, 4);
        let img = film.image();
        // (6 + 2) / 4 paths on top of the camera's 1.
        assert_eq!(img.pixels[0], Rgb::new(3.0, 1.0, 1.0 + 1.0));
        assert!(img.pixels[1..].iter().all(|p| *p == Rgb::ZERO));
        // Splats 6, 2, 0, 0 over four paths: (E[c^2] - mean^2) / (n - 1) for the mean.
        let v = film.variance_image().pixels[0].r as f64;
        let (m, sq) = (2.0, (36.0 + 4.0) / 4.0);
        assert!((v - (sq - m * m) / 3.0).abs() < 1e-6, "{v}");
        // Light paths brought (2, 0, 1) of (3, 1, 2).
        let lum = |r: f32, g: f32, b: f32| f64::from(Rgb::new(r, g, b).luminance());
        let share = film.light_path_share().expect("light paths");
        assert!(
            (share - lum(2.0, 0.0, 1.0) / lum(3.0, 1.0, 2.0)).abs() < 1e-6,
            "{share}"
        );
        assert_eq!(Film::new(2, 2).light_path_share(), None);
        // Their own image and its variance: the splats' part alone.
        let (light, variance) = film.light_path_images().expect("light paths");
        assert_eq!(light.pixels[0], Rgb::new(2.0, 0.0, 1.0));
        assert!(light.pixels[1..].iter().all(|p| *p == Rgb::ZERO));
        assert_eq!(variance.pixels[0].r as f64, v as f64);
        // The camera's single sample has no variance: all of it is the light paths'.
        assert_eq!(film.light_path_variance_share(), Some(1.0));
        assert!(Film::new(2, 2).light_path_images().is_none());
    }

    #[test]
    fn out_of_range_samples_are_refused_and_saturated_squares_read_as_infinite_variance() {
        assert!(!Pixel::accepts(Rgb::new(f32::NAN, 0.0, 0.0)));
        assert!(!Pixel::accepts(Rgb::new(0.0, 3e9, 0.0)));
        assert!(Pixel::accepts(Rgb::new(0.0, 2e9, -2e9)));
        let mut p = Pixel::default();
        for _ in 0..8 {
            p.add(Rgb::new(2e9, 1.0, 1.0));
        }
        assert_eq!(p.variance_of_mean()[0], f64::INFINITY);
        assert!((p.mean()[0] / 2e9 - 1.0).abs() < 1e-7);
        assert_eq!(p.variance_of_mean()[1], 0.0);
    }
}
