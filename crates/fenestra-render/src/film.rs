//! The film: per-pixel f64 sums of samples and of their squares (box filter over the pixel),
//! so that the image and the variance of each pixel's mean come out of one render.

use fenestra_core::image::{Estimate, Image};
use fenestra_core::Rgb;

/// One pixel's accumulators.
#[derive(Clone, Copy, Debug, Default)]
pub struct Pixel {
    /// Sum of the samples, per channel.
    pub sum: [f64; 3],
    /// Sum of their squares, per channel.
    pub sum_sq: [f64; 3],
    /// Samples added.
    pub count: u32,
}

impl Pixel {
    /// Adds one sample.
    pub fn add(&mut self, c: Rgb) {
        for (i, v) in c.to_array().into_iter().enumerate() {
            self.sum[i] += v as f64;
            self.sum_sq[i] += v as f64 * v as f64;
        }
        self.count += 1;
    }

    /// Sets the pixel to an estimate `mean` whose mean has the variance `variance` (per
    /// channel), for estimators that combine their samples otherwise than by averaging
    /// (seed 004's inverse-variance weighting of passes): stored as the two samples
    /// mean +- sqrt(variance), whose mean and variance of the mean are exactly these.
    pub fn set_estimate(&mut self, mean: [f64; 3], variance: [f64; 3]) {
        *self = Pixel::default();
        for sign in [1.0, -1.0] {
            for i in 0..3 {
                let v = mean[i] + sign * variance[i].max(0.0).sqrt();
                self.sum[i] += v;
                self.sum_sq[i] += v * v;
            }
            self.count += 1;
        }
    }

    /// The sample mean, per channel.
    pub fn mean(&self) -> [f64; 3] {
        let n = self.count.max(1) as f64;
        self.sum.map(|s| s / n)
    }

    /// Variance of the pixel mean (sample variance / n), per channel.
    pub fn variance_of_mean(&self) -> [f64; 3] {
        let n = self.count as f64;
        if n < 2.0 {
            return [0.0; 3];
        }
        std::array::from_fn(|i| {
            let mean = self.sum[i] / n;
            ((self.sum_sq[i] / n - mean * mean) * n / (n - 1.0)).max(0.0) / n
        })
    }
}

/// The image being rendered: one [`Pixel`] of accumulators per pixel, row-major.
#[derive(Clone, Debug)]
pub struct Film {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major, top row first.
    pub pixels: Vec<Pixel>,
}

impl Film {
    /// An empty film.
    pub fn new(width: u32, height: u32) -> Self {
        Film {
            width,
            height,
            pixels: vec![Pixel::default(); width as usize * height as usize],
        }
    }

    fn to_image(&self, f: impl Fn(&Pixel) -> [f64; 3]) -> Image {
        let mut img = Image::new(self.width as usize, self.height as usize);
        for (dst, p) in img.pixels.iter_mut().zip(&self.pixels) {
            let v = f(p);
            *dst = Rgb::new(v[0] as f32, v[1] as f32, v[2] as f32);
        }
        img
    }

    /// The rendered image: each pixel's sample mean.
    pub fn image(&self) -> Image {
        self.to_image(Pixel::mean)
    }

    /// The image and its per-pixel variance of the mean.
    pub fn estimate(&self) -> Estimate {
        Estimate {
            mean: self.image(),
            variance: self.variance_image(),
        }
    }

    /// Per-pixel variance of the mean.
    pub fn variance_image(&self) -> Image {
        self.to_image(Pixel::variance_of_mean)
    }

    /// (smallest, largest) samples taken by any pixel.
    pub fn sample_count_range(&self) -> (u32, u32) {
        let min = self.pixels.iter().map(|p| p.count).min().unwrap_or(0);
        let max = self.pixels.iter().map(|p| p.count).max().unwrap_or(0);
        (min, max)
    }
}
