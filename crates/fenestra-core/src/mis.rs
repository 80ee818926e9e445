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
            MisHeuristic::Power { beta } => {
                // pa^beta / (pa^beta + pb^beta) = 1 / (1 + r^beta) with r = pb / pa, which
                // neither overflows nor underflows where it matters (r = inf gives 0).
                let r = pb / pa;
                let rb = if beta == 2.0 { r * r } else { r.powf(beta) };
                1.0 / (1.0 + rb)
            }
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
}
