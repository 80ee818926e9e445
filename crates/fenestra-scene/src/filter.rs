//! Pixel reconstruction filters, as pbrt-v4's PixelFilter defines them: box, triangle,
//! gaussian, mitchell and sinc (Lanczos), all separable. A camera sample's film position is
//! drawn from the filter around the pixel's centre (filter importance sampling), so a pixel
//! stays the plain average of its own samples: no splatting between pixels, the same pixels
//! for any thread count. Box and triangle are sampled exactly; the others from a table of
//! their profile, linear over 512 pieces per axis. Mitchell and sinc have negative lobes
//! that this sampling cannot give: their positive part is used (the pbrt-v4 reader warns).

use fenestra_core::Vec2;
use std::sync::Arc;

/// Pieces of the tabulated profiles.
const PIECES: usize = 512;

/// A filter's profile along one axis.
#[derive(Clone, Debug, PartialEq)]
pub enum FilterShape {
    /// Constant.
    Box,
    /// Linear falloff to zero at the radius.
    Triangle,
    /// exp(-x^2 / (2 sigma^2)) less its value at the radius.
    Gaussian {
        /// Standard deviation in pixels.
        sigma: f32,
    },
    /// Mitchell-Netravali's cubic with parameters B and C over x in [-radius, radius].
    Mitchell {
        /// B.
        b: f32,
        /// C.
        c: f32,
    },
    /// sinc(x) sinc(x / tau), the Lanczos window.
    Sinc {
        /// Cycles of the window.
        tau: f32,
    },
}

/// A separable pixel filter of `radius` pixels along x and y.
#[derive(Clone)]
pub struct PixelFilter {
    shape: FilterShape,
    radius: Vec2,
    /// Inverse-CDF tables per axis for the tabulated shapes.
    tables: Option<Arc<[Profile; 2]>>,
    /// The one-pixel box, decided once: `sample` runs for every camera ray.
    pixel_box: bool,
}

impl std::fmt::Debug for PixelFilter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // The tables follow from the shape and radius.
        f.debug_struct("PixelFilter")
            .field("shape", &self.shape)
            .field("radius", &self.radius)
            .finish()
    }
}

impl PartialEq for PixelFilter {
    fn eq(&self, other: &Self) -> bool {
        self.shape == other.shape && self.radius == other.radius
    }
}

impl Default for PixelFilter {
    /// The box of one pixel: a uniform point of the pixel, fenestra's own default.
    fn default() -> Self {
        PixelFilter::new(FilterShape::Box, Vec2::splat(0.5))
    }
}

impl PixelFilter {
    /// A filter of `shape` and half-widths `radius`, which must be positive and finite.
    pub fn new(shape: FilterShape, radius: Vec2) -> Self {
        let tables = match shape {
            FilterShape::Box | FilterShape::Triangle => None,
            _ => Some(Arc::new([
                Profile::new(&shape, radius.x),
                Profile::new(&shape, radius.y),
            ])),
        };
        PixelFilter {
            pixel_box: shape == FilterShape::Box && radius == Vec2::splat(0.5),
            shape,
            radius,
            tables,
        }
    }

    /// The profile.
    pub fn shape(&self) -> &FilterShape {
        &self.shape
    }

    /// Half-widths along x and y in pixels.
    pub fn radius(&self) -> Vec2 {
        self.radius
    }

    /// pbrt-v4's default: a gaussian of radius 1.5 and sigma 0.5.
    pub fn pbrt_default() -> Self {
        PixelFilter::new(FilterShape::Gaussian { sigma: 0.5 }, Vec2::splat(1.5))
    }

    /// Whether this is the one-pixel box, whose samples are uniform points of the pixel.
    pub fn is_pixel_box(&self) -> bool {
        self.pixel_box
    }

    /// The film position of a sample from `u` in [0,1)^2, relative to the pixel's top-left
    /// corner: the pixel's centre plus an offset drawn from the filter.
    pub fn sample(&self, u: Vec2) -> Vec2 {
        if self.is_pixel_box() {
            return u;
        }
        let offset = match (&self.shape, &self.tables) {
            (FilterShape::Box, _) => (u * 2.0 - Vec2::ONE) * self.radius,
            (FilterShape::Triangle, _) => Vec2::new(tent(u.x), tent(u.y)) * self.radius,
            (_, Some(t)) => Vec2::new(t[0].sample(u.x), t[1].sample(u.y)),
            (_, None) => Vec2::ZERO,
        };
        Vec2::splat(0.5) + offset
    }

    /// The density with which [`PixelFilter::sample`] gives the film position `at` (relative
    /// to the pixel's top-left corner, as `sample` returns it), per square pixel: what a
    /// light path's vertex seen at `at` counts for this pixel.
    pub fn density(&self, at: Vec2) -> f32 {
        if self.is_pixel_box() {
            let inside = (0.0..1.0).contains(&at.x) && (0.0..1.0).contains(&at.y);
            return if inside { 1.0 } else { 0.0 };
        }
        let d = at - Vec2::splat(0.5);
        let axis = |x: f32, r: f32, k: usize| -> f32 {
            if !(x.abs() <= r) {
                return 0.0;
            }
            match (&self.shape, &self.tables) {
                (FilterShape::Box, _) => 0.5 / r,
                (FilterShape::Triangle, _) => (1.0 - x.abs() / r) / r,
                (_, Some(t)) => t[k].density(x),
                (_, None) => 0.0,
            }
        };
        axis(d.x, self.radius.x, 0) * axis(d.y, self.radius.y, 1)
    }

    /// The profile's value at offset `x` from the centre along one axis of half-width `r`
    /// (negative lobes included).
    pub fn profile(&self, x: f32, r: f32) -> f32 {
        profile(&self.shape, x, r)
    }
}

/// The unit tent on [-1, 1], sampled exactly.
fn tent(u: f32) -> f32 {
    if u < 0.5 {
        (2.0 * u).sqrt() - 1.0
    } else {
        1.0 - (2.0 - 2.0 * u).sqrt()
    }
}

fn profile(shape: &FilterShape, x: f32, r: f32) -> f32 {
    if x.abs() > r {
        return 0.0;
    }
    match *shape {
        FilterShape::Box => 1.0,
        FilterShape::Triangle => 1.0 - x.abs() / r,
        FilterShape::Gaussian { sigma } => {
            let g = |x: f32| (-x * x / (2.0 * sigma * sigma)).exp();
            (g(x) - g(r)).max(0.0)
        }
        FilterShape::Mitchell { b, c } => {
            // Mitchell and Netravali 1988, over [-2, 2] scaled to the radius.
            let x = (2.0 * x / r).abs();
            if x < 1.0 {
                ((12.0 - 9.0 * b - 6.0 * c) * x.powi(3)
                    + (-18.0 + 12.0 * b + 6.0 * c) * x * x
                    + (6.0 - 2.0 * b))
                    / 6.0
            } else {
                ((-b - 6.0 * c) * x.powi(3)
                    + (6.0 * b + 30.0 * c) * x * x
                    + (-12.0 * b - 48.0 * c) * x
                    + (8.0 * b + 24.0 * c))
                    / 6.0
            }
        }
        FilterShape::Sinc { tau } => {
            let sinc = |x: f32| {
                let x = x.abs();
                if x < 1e-5 {
                    1.0
                } else {
                    let px = std::f32::consts::PI * x;
                    px.sin() / px
                }
            };
            sinc(x) * sinc(x / tau)
        }
    }
}

/// The positive part of a profile on [-r, r], linear between `PIECES + 1` nodes, with its
/// cumulative areas for sampling.
#[derive(Clone, Debug)]
struct Profile {
    r: f32,
    values: Vec<f32>,
    /// Area under the linear profile, in units of its pieces.
    area: f32,
    /// Area up to each node, normalised to end at 1.
    cdf: Vec<f32>,
}

impl Profile {
    fn new(shape: &FilterShape, r: f32) -> Self {
        let step = 2.0 * r / PIECES as f32;
        let values: Vec<f32> = (0..=PIECES)
            .map(|i| profile(shape, -r + i as f32 * step, r).max(0.0))
            .collect();
        let mut cdf = Vec::with_capacity(PIECES + 1);
        let mut area = 0.0f64;
        cdf.push(0.0);
        for w in values.windows(2) {
            area += 0.5 * (w[0] + w[1]) as f64;
            cdf.push(area as f32);
        }
        let total = area as f32;
        if total > 0.0 {
            cdf.iter_mut().for_each(|c| *c /= total);
        }
        Profile {
            r,
            values,
            area: total,
            cdf,
        }
    }

    /// The density of [`Profile::sample`]'s offsets at `x` in [-r, r].
    fn density(&self, x: f32) -> f32 {
        let step = 2.0 * self.r / PIECES as f32;
        let at = ((x + self.r) / step).clamp(0.0, PIECES as f32);
        let i = (at as usize).min(PIECES - 1);
        let s = at - i as f32;
        let v = self.values[i] * (1.0 - s) + self.values[i + 1] * s;
        if self.area > 0.0 {
            v / (self.area * step)
        } else {
            0.0
        }
    }

    /// An offset in [-r, r] with density proportional to the linear profile.
    fn sample(&self, u: f32) -> f32 {
        // The piece whose cumulative area brackets u.
        let i = self.cdf.partition_point(|&c| c <= u).clamp(1, PIECES) - 1;
        let (a, b) = (self.values[i], self.values[i + 1]);
        let width = self.cdf[i + 1] - self.cdf[i];
        let t = if width > 0.0 {
            ((u - self.cdf[i]) / width).clamp(0.0, 1.0)
        } else {
            0.5
        };
        // Within the piece the density is linear from a to b: solve
        // (a s + (b - a) s^2 / 2) / ((a + b) / 2) = t for s in [0, 1].
        let s = if (a - b).abs() <= 1e-6 * (a + b) {
            t
        } else {
            let disc = a * a + (b * b - a * a) * t;
            (disc.max(0.0).sqrt() - a) / (b - a)
        };
        let step = 2.0 * self.r / PIECES as f32;
        -self.r + (i as f32 + s.clamp(0.0, 1.0)) * step
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Rng;
    use fenestra_eval::chi2::{chi2, Chi2, MIN_EXPECTED};

    /// The chi-square test of the x offsets of `n` samples against `expected` (a density up
    /// to a factor on [-r, r]) over `bins` bins (the shared harness).
    fn chi_square(filter: &PixelFilter, expected: impl Fn(f32) -> f32) -> Chi2 {
        let (bins, n) = (40, 200_000);
        let r = filter.radius.x;
        let mut counts = vec![0.0; bins];
        let mut rng = Rng::new(7);
        for _ in 0..n {
            let p = filter.sample(rng.next_2d()) - Vec2::splat(0.5);
            assert!(p.x.abs() <= r * 1.0001 && p.y.abs() <= filter.radius.y * 1.0001);
            let b = ((p.x + r) / (2.0 * r) * bins as f32) as usize;
            counts[b.min(bins - 1)] += 1.0;
        }
        // Each bin's share by a fine midpoint rule.
        let sub = 200;
        let mass: Vec<f64> = (0..bins)
            .map(|b| {
                (0..sub)
                    .map(|k| {
                        let t = (b as f32 + (k as f32 + 0.5) / sub as f32) / bins as f32;
                        expected(-r + 2.0 * r * t) as f64
                    })
                    .sum::<f64>()
            })
            .collect();
        let total: f64 = mass.iter().sum();
        // Where the profile crosses zero between two of its table's nodes, the sampler's
        // linear pieces put a few samples beside the crossing, where the profile's positive
        // part expects almost none: bins expecting fewer than five take no part, and hold
        // few samples.
        let (mut observed, mut expected) = (Vec::new(), Vec::new());
        for (&c, m) in counts.iter().zip(&mass) {
            let e = m / total * n as f64;
            if e >= MIN_EXPECTED {
                observed.push(c);
                expected.push(e);
            } else {
                assert!(c < 20.0, "{c} samples where the filter is about 0");
            }
        }
        chi2(&observed, &expected, 0.0).expect("same bins")
    }

    #[test]
    fn samples_follow_each_filter_chi_square() {
        let third = 1.0 / 3.0;
        for (shape, r) in [
            (FilterShape::Box, 1.0),
            (FilterShape::Triangle, 2.0),
            (FilterShape::Gaussian { sigma: 0.5 }, 1.5),
            (FilterShape::Mitchell { b: third, c: third }, 2.0),
            (FilterShape::Sinc { tau: 3.0 }, 4.0),
        ] {
            let filter = PixelFilter::new(shape.clone(), Vec2::new(r, r * 0.5));
            let test = chi_square(&filter, |x| filter.profile(x, r).max(0.0));
            assert!(test.p_value > 1e-3, "{shape:?}: {test:?}");
        }
        // And the test sees a wrong density: gaussian samples against the triangle.
        let gaussian = PixelFilter::new(FilterShape::Gaussian { sigma: 0.5 }, Vec2::splat(2.0));
        let test = chi_square(&gaussian, |x| 1.0 - x.abs() / 2.0);
        assert!(test.p_value < 1e-6, "{test:?}");
    }

    #[test]
    fn the_density_is_that_of_the_samples_and_integrates_to_one() {
        let third = 1.0 / 3.0;
        for (shape, r) in [
            (FilterShape::Box, 0.5),
            (FilterShape::Box, 1.0),
            (FilterShape::Triangle, 2.0),
            (FilterShape::Gaussian { sigma: 0.5 }, 1.5),
            (FilterShape::Mitchell { b: third, c: third }, 2.0),
        ] {
            let filter = PixelFilter::new(shape.clone(), Vec2::new(r, r * 0.5));
            // Separable: the density along x at the centre row is the x marginal's, up to a
            // factor.
            let test = chi_square(&filter, |x| filter.density(Vec2::new(0.5 + x, 0.5)));
            assert!(test.p_value > 1e-3, "{shape:?}: {test:?}");
            let n = 400;
            let (rx, ry) = (r, r * 0.5);
            let cell = (2.0 * rx / n as f32) * (2.0 * ry / n as f32);
            let total: f64 = (0..n * n)
                .map(|k| {
                    let x = -rx + 2.0 * rx * ((k % n) as f32 + 0.5) / n as f32;
                    let y = -ry + 2.0 * ry * ((k / n) as f32 + 0.5) / n as f32;
                    (filter.density(Vec2::new(0.5 + x, 0.5 + y)) * cell) as f64
                })
                .sum();
            assert!((total - 1.0).abs() < 2e-3, "{shape:?}: {total}");
            assert_eq!(filter.density(Vec2::new(0.5 + 1.01 * rx, 0.5)), 0.0);
        }
    }

    #[test]
    fn the_pixel_box_is_the_uniform_pixel_and_others_centre_on_it() {
        let u = Vec2::new(0.3, 0.8);
        assert_eq!(PixelFilter::default().sample(u), u);
        let tri = PixelFilter::new(FilterShape::Triangle, Vec2::splat(2.0));
        assert_eq!(tri.sample(Vec2::splat(0.5)), Vec2::splat(0.5));
        let g = PixelFilter::pbrt_default();
        assert!((g.sample(Vec2::splat(0.5)) - Vec2::splat(0.5)).length() < 1e-3);
    }
}
