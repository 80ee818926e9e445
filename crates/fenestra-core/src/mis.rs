//! Multiple importance sampling weights (seed 000 §4.2, §5.2; Veach 1997).

use serde::{Deserialize, Serialize};

/// How two sampling techniques are combined.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum MisHeuristic {
    /// w_i = p_i / sum_j p_j.
    Balance,
    /// w_i = p_i^beta / sum_j p_j^beta (beta = 2 is Veach's power heuristic).
    Power {
        /// The exponent beta.
        beta: f32,
    },
}

impl MisHeuristic {
    /// Weight of the technique with density `pa` against one with density `pb`,
    /// both taking one sample.
    pub fn weight(self, pa: f32, pb: f32) -> f32 {
        if pa <= 0.0 {
            return 0.0;
        }
        if !pa.is_finite() {
            return 1.0;
        }
        match self {
            MisHeuristic::Balance => pa / (pa + pb),
            // pa^beta / (pa^beta + pb^beta) = 1 / (1 + r^beta) with r = pb / pa, which
            // neither overflows nor underflows where it matters (r = inf gives 0).
            MisHeuristic::Power { .. } => 1.0 / (1.0 + self.powered(pb / pa)),
        }
    }

    /// r^beta (r for the balance heuristic).
    fn powered(self, r: f32) -> f32 {
        match self {
            MisHeuristic::Balance => r,
            MisHeuristic::Power { beta: 2.0 } => r * r,
            MisHeuristic::Power { beta } => r.powf(beta),
        }
    }

    /// The density that stands for techniques of densities `pa` and `pb` together against a
    /// third: (pa^beta + pb^beta)^(1/beta), so that `weight(pc, combined(pa, pb))` is the
    /// third's weight against both.
    pub fn combined(self, pa: f32, pb: f32) -> f32 {
        match self {
            MisHeuristic::Balance => pa + pb,
            MisHeuristic::Power { beta: 2.0 } => pa.hypot(pb),
            MisHeuristic::Power { beta } => (pa.powf(beta) + pb.powf(beta)).powf(1.0 / beta),
        }
    }

    /// What multiplies a technique's weight `w` against others once one more technique
    /// joins them, `r` times as dense as it for the same sample: w / (1 + w r^beta) is its
    /// weight against all (1 / w = sum of (p_j / p)^beta, to which (p_new / p)^beta adds).
    pub fn with_third(self, w: f32, r: f32) -> f32 {
        let f = 1.0 / (1.0 + w * self.powered(r));
        if f.is_nan() {
            1.0
        } else {
            f
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_sum_to_one() {
        for h in [
            MisHeuristic::Balance,
            MisHeuristic::Power { beta: 2.0 },
            MisHeuristic::Power { beta: 3.5 },
        ] {
            for (a, b) in [(1.0, 3.0), (1e-30, 1e30), (5.0, 5.0), (1e20, 1e-20)] {
                let s = h.weight(a, b) + h.weight(b, a);
                assert!((s - 1.0).abs() < 1e-5, "{h:?} {a} {b}: {s}");
            }
        }
        assert_eq!(MisHeuristic::Power { beta: 2.0 }.weight(1.0, 3.0), 0.1);
    }

    #[test]
    fn three_techniques_weighted_pairwise_sum_to_one() {
        for h in [
            MisHeuristic::Balance,
            MisHeuristic::Power { beta: 2.0 },
            MisHeuristic::Power { beta: 3.5 },
        ] {
            for (a, b, c) in [
                (1.0, 3.0, 2.0),
                (1e-3, 5.0, 1e3),
                (7.0, 0.0, 0.5),
                (0.0, 2.0, 2.0),
            ] {
                // a and b weighed against each other, then each against c.
                let wa = h.weight(a, b) * h.with_third(h.weight(a, b), c / a);
                let wb = h.weight(b, a) * h.with_third(h.weight(b, a), c / b);
                let wc = h.weight(c, h.combined(a, b));
                let s = wa + wb + wc;
                assert!((s - 1.0).abs() < 1e-5, "{h:?} {a} {b} {c}: {s}");
            }
        }
    }
}
