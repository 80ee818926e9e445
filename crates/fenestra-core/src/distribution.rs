//! Piecewise-constant distributions in one and two dimensions, for picking lights by power
//! and for importance-sampling environment images.

use glam::Vec2;

/// A piecewise-constant density on [0, 1) with `n` equal bins.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    func: Vec<f32>,
    cdf: Vec<f32>,
    integral: f32,
}

impl Distribution1D {
    /// `func` must be non-negative; an all-zero (or empty) function becomes uniform.
    pub fn new(func: &[f32]) -> Self {
        let n = func.len().max(1);
        let mut f: Vec<f32> = func
            .iter()
            .map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 })
            .collect();
        if f.is_empty() {
            f.push(1.0);
        }
        let mut cdf = vec![0.0f32; n + 1];
        let mut acc = 0.0f64;
        for i in 0..n {
            acc += f[i] as f64 / n as f64;
            cdf[i + 1] = acc as f32;
        }
        let integral = acc as f32;
        if integral <= 0.0 {
            f.iter_mut().for_each(|v| *v = 1.0);
            for (i, c) in cdf.iter_mut().enumerate() {
                *c = i as f32 / n as f32;
            }
            return Distribution1D {
                func: f,
                cdf,
                integral: 1.0,
            };
        }
        for c in cdf.iter_mut() {
            *c /= integral;
        }
        cdf[n] = 1.0;
        Distribution1D {
            func: f,
            cdf,
            integral,
        }
    }

    /// Number of pieces.
    pub fn len(&self) -> usize {
        self.func.len()
    }
    /// Whether there are no pieces.
    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }
    /// Integral of the unnormalised function over [0, 1).
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// Probability of bin `i` when sampling discretely.
    pub fn discrete_pmf(&self, i: usize) -> f32 {
        self.func
            .get(i)
            .map_or(0.0, |f| f / (self.integral * self.len() as f32))
    }

    /// Picks a bin with probability proportional to its value; returns (bin, pmf, u remapped
    /// to [0,1) within the bin).
    pub fn sample_discrete(&self, u: f32) -> (usize, f32, f32) {
        let i = self.find(u);
        let width = self.cdf[i + 1] - self.cdf[i];
        let remapped = if width > 0.0 {
            ((u - self.cdf[i]) / width).clamp(0.0, 1.0 - f32::EPSILON)
        } else {
            0.0
        };
        (i, self.discrete_pmf(i), remapped)
    }

    /// Samples a continuous x in [0,1); returns (x, density, bin).
    pub fn sample_continuous(&self, u: f32) -> (f32, f32, usize) {
        let (i, _, du) = self.sample_discrete(u);
        let x = ((i as f32 + du) / self.len() as f32).min(1.0 - f32::EPSILON);
        (x, self.func[i] / self.integral, i)
    }

    /// Density at `x` in [0, 1) of [`Distribution1D::sample_continuous`].
    pub fn pdf_continuous(&self, x: f32) -> f32 {
        let i = ((x * self.len() as f32) as usize).min(self.len() - 1);
        self.func[i] / self.integral
    }

    fn find(&self, u: f32) -> usize {
        // The first bin with cdf[i] <= u < cdf[i + 1]; such a bin has non-zero width.
        let u = u.clamp(0.0, 1.0 - f32::EPSILON);
        self.cdf[1..]
            .partition_point(|&c| c <= u)
            .min(self.len() - 1)
    }
}

/// A piecewise-constant density on [0,1)^2 from a row-major `width` x `height` grid:
/// a marginal over rows and one conditional per row.
#[derive(Clone, Debug)]
pub struct Distribution2D {
    conditional: Vec<Distribution1D>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// The distribution of the non-negative `func` given per cell.
    pub fn new(func: &[f32], width: usize, height: usize) -> Self {
        let conditional: Vec<Distribution1D> = (0..height)
            .map(|y| Distribution1D::new(&func[y * width..(y + 1) * width]))
            .collect();
        // The rows' own integrals: a row of zeros samples uniformly if picked, but it is
        // never picked unless every row is zero.
        let rows: Vec<f32> = (func.chunks(width.max(1)).take(height))
            .map(|row| {
                let sum: f64 = (row.iter())
                    .map(|&v| {
                        if v.is_finite() {
                            f64::from(v.max(0.0))
                        } else {
                            0.0
                        }
                    })
                    .sum();
                (sum / row.len().max(1) as f64) as f32
            })
            .collect();
        let marginal = Distribution1D::new(&rows);
        Distribution2D {
            conditional,
            marginal,
        }
    }

    /// Returns (point in [0,1)^2 as (x, y), density).
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (y, pdf_y, row) = self.marginal.sample_continuous(u.y);
        let (x, pdf_x, _) = self.conditional[row].sample_continuous(u.x);
        (Vec2::new(x, y), pdf_x * pdf_y)
    }

    /// Density of [`Distribution2D::sample`] at `p` in [0,1)^2.
    pub fn pdf(&self, p: Vec2) -> f32 {
        let h = self.conditional.len();
        let row = ((p.y * h as f32) as usize).min(h - 1);
        self.conditional[row].pdf_continuous(p.x) * self.marginal.pdf_continuous(p.y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn discrete_sampling_follows_the_function() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0, 0.0]);
        assert_eq!(d.discrete_pmf(0), 0.25);
        assert_eq!(d.discrete_pmf(2), 0.75);
        let mut counts = [0u32; 4];
        for i in 0..1000 {
            counts[d.sample_discrete((i as f32 + 0.5) / 1000.0).0] += 1;
        }
        assert_eq!(counts, [250, 0, 750, 0]);
    }

    #[test]
    fn continuous_density_integrates_to_one() {
        let f = [0.5, 2.0, 0.0, 7.0, 1.0];
        let d = Distribution1D::new(&f);
        let n = 10_000;
        let integral: f32 = (0..n)
            .map(|i| d.pdf_continuous((i as f32 + 0.5) / n as f32))
            .sum::<f32>()
            / n as f32;
        assert!((integral - 1.0).abs() < 1e-4);
        for i in 0..100 {
            let (x, pdf, _) = d.sample_continuous(i as f32 / 100.0);
            assert!((pdf - d.pdf_continuous(x)).abs() < 1e-5);
            assert!(pdf > 0.0, "never lands in a zero bin");
        }
    }

    #[test]
    fn two_d_never_picks_a_row_of_zeros() {
        // One bright cell among rows of zeros: every sample lands in it.
        let mut f = vec![0.0f32; 16 * 16];
        f[5 * 16 + 9] = 3.0;
        let d = Distribution2D::new(&f, 16, 16);
        for i in 0..64 {
            let u = Vec2::new((i as f32 * 0.618).fract(), (i as f32 + 0.5) / 64.0);
            let (p, pdf) = d.sample(u);
            assert_eq!(((p.x * 16.0) as usize, (p.y * 16.0) as usize), (9, 5));
            assert!((pdf - 256.0).abs() < 1e-2, "{pdf}");
        }
    }

    #[test]
    fn two_d_density_matches_its_samples() {
        let f: Vec<f32> = (0..12).map(|i| (i % 5) as f32).collect();
        let d = Distribution2D::new(&f, 4, 3);
        for i in 0..50 {
            let u = Vec2::new((i as f32 * 0.618).fract(), (i as f32 + 0.5) / 50.0);
            let (p, pdf) = d.sample(u);
            assert!((pdf - d.pdf(p)).abs() < 1e-4 * pdf.max(1.0));
        }
    }
}
