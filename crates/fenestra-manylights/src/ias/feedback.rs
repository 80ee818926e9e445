//! The feedback of seed 004's passes: statistics per light cluster and the PDFs built from
//! them (§3.3.3, §3.5.4, eq. 3.2, 3.7, 3.8, App. A.2).

use fenestra_core::Vec3;

/// Weights (uniform, block, pixel) of the PDFs combined in pass `j` (eq. 3.2): uniform only
/// at first, then mostly the block, then mostly the pixel (the shape of the seed's Fig. 3.5,
/// whose values the text does not give); the uniform part never vanishes.
pub(super) fn weights(pass: u32) -> [f32; 3] {
    match pass {
        0 => [1.0, 0.0, 0.0],
        1 => [0.3, 0.5, 0.2],
        2 => [0.2, 0.45, 0.35],
        3 => [0.15, 0.35, 0.5],
        4 => [0.1, 0.25, 0.65],
        _ => [0.1, 0.15, 0.75],
    }
}

/// A cluster's F = C / sqrt(u) (eq. 3.7) for the block PDF, `None` where the undersampling
/// guard (§4.6.2) does not trust it yet: no samples, or fewer than four, all occluded.
pub(super) fn guarded(s: &Stat) -> Option<f64> {
    if s.count == 0 || s.count < 4 && s.visible == 0 {
        None
    } else {
        Some(s.weight().unwrap_or(0.0))
    }
}

/// A cluster's F for the pixel PDF: zero without samples.
pub(super) fn unguarded(s: &Stat) -> Option<f64> {
    Some(s.weight().unwrap_or(0.0))
}

/// A feedback PDF over a cut from its clusters' F (eq. 3.8): in proportion to F, a cluster
/// whose F is not trusted (`None`) given the mean F of the others. `None` when nothing has
/// weight yet.
pub(super) fn component(f: impl Iterator<Item = Option<f64>> + Clone) -> Option<Vec<f64>> {
    let (mut known, mut count) = (0.0f64, 0usize);
    for v in f.clone().flatten() {
        known += v;
        count += 1;
    }
    let mean = if count == 0 {
        0.0
    } else {
        known / count as f64
    };
    let mut f: Vec<f64> = f.map(|v| v.unwrap_or(mean)).collect();
    let total: f64 = f.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return None;
    }
    for v in &mut f {
        *v /= total;
    }
    Some(f)
}

/// The PDF of pass `pass` over `n` clusters (eq. 3.2): the uniform, block and pixel PDFs by
/// the pass's weights, a missing feedback PDF's weight given to the uniform one. Every
/// cluster keeps at least the uniform part's probability.
pub(super) fn blend(
    n: usize,
    pass: u32,
    block: Option<Vec<f64>>,
    pixel: Option<Vec<f64>>,
) -> Vec<f32> {
    let [mut cu, cb, cp] = weights(pass).map(f64::from);
    if block.is_none() {
        cu += cb;
    }
    if pixel.is_none() {
        cu += cp;
    }
    (0..n)
        .map(|i| {
            let b = block.as_ref().map_or(0.0, |b| cb * b[i]);
            let p = pixel.as_ref().map_or(0.0, |p| cp * p[i]);
            (cu / n as f64 + b + p) as f32
        })
        .collect()
}

/// Which of six classes a normal falls in (the cube face it points to, §3.5.4).
pub(super) fn normal_class(n: Vec3) -> usize {
    let a = n.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    2 * axis + usize::from(n[axis] < 0.0)
}

/// Running sums of the evaluations of one cluster (eq. 3.6 and the visible fraction u).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Stat {
    pub(super) sum: f64,
    pub(super) count: u32,
    pub(super) visible: u32,
}

impl Stat {
    /// F = C / sqrt(u) (eq. 3.7), `None` without samples.
    fn weight(&self) -> Option<f64> {
        if self.count == 0 {
            return None;
        }
        let c = self.sum / self.count as f64;
        let u = self.visible as f64 / self.count as f64;
        Some(if u > 0.0 { c / u.sqrt() } else { 0.0 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The variance of one sample of two lights of exitant radiance L_i, visible fractions
    /// u_i, the first picked with probability p (App. A.2, eq. A.4).
    fn variance(p: f64, l: [f64; 2], u: [f64; 2]) -> f64 {
        let second = u[0] * l[0] * l[0] / p + u[1] * l[1] * l[1] / (1.0 - p);
        let mean = u[0] * l[0] + u[1] * l[1];
        second - mean * mean
    }

    #[test]
    fn c_over_sqrt_u_minimises_the_variance_of_partly_visible_lights() {
        for (l, u) in [
            ([1.0, 1.0], [1.0, 0.25]),
            ([3.0, 1.0], [0.1, 0.9]),
            ([0.5, 2.0], [0.6, 0.05]),
        ] {
            // The statistics such lights leave: C = u L as the mean contribution, u the
            // visible share (1000 samples each).
            let stat = |i: usize| Stat {
                sum: 1000.0 * u[i] * l[i],
                count: 1000,
                visible: (1000.0 * u[i]) as u32,
            };
            let pdf = component([stat(0), stat(1)].iter().map(unguarded)).expect("weights");
            // The numerical minimum over p, on a fine grid.
            let best = (1..10_000)
                .map(|k| k as f64 / 10_000.0)
                .min_by(|&a, &b| variance(a, l, u).total_cmp(&variance(b, l, u)))
                .expect("grid");
            assert!(
                (pdf[0] - best).abs() < 2e-3,
                "L {l:?} u {u:?}: C/sqrt(u) gives {} where the variance is least at {best}",
                pdf[0]
            );
            // Proportional to contribution alone would be worse wherever u differ.
            let by_c = u[0] * l[0] / (u[0] * l[0] + u[1] * l[1]);
            assert!(variance(pdf[0], l, u) <= variance(by_c, l, u) + 1e-12);
        }
    }

    #[test]
    fn no_cluster_ever_gets_zero_probability() {
        // A cluster the feedback says is dark (sampled, never visible) still keeps the
        // uniform share of every pass: the estimator stays unbiased if the feedback is wrong.
        let dark = Stat {
            sum: 0.0,
            count: 40,
            visible: 0,
        };
        let lit = Stat {
            sum: 40.0,
            count: 40,
            visible: 40,
        };
        let stats = [lit, dark, lit];
        for pass in 0..20 {
            let pdf = blend(
                3,
                pass,
                component(stats.iter().map(guarded)),
                component(stats.iter().map(unguarded)),
            );
            let total: f32 = pdf.iter().sum();
            assert!((total - 1.0).abs() < 1e-5, "pass {pass}: sums to {total}");
            assert!(pdf[1] >= 0.1 / 3.0 - 1e-6, "pass {pass}: {pdf:?}");
        }
        // The guard: a cluster with under four samples, all occluded, is not trusted yet.
        let barely = Stat {
            sum: 0.0,
            count: 3,
            visible: 0,
        };
        let pdf = component([lit, barely].iter().map(guarded)).expect("weights");
        assert!(
            (pdf[0] - 0.5).abs() < 1e-9 && (pdf[1] - 0.5).abs() < 1e-9,
            "{pdf:?}"
        );
        assert_eq!(
            component([lit, barely].iter().map(unguarded)).expect("weights")[1],
            0.0
        );
    }
}
