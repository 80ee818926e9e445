//! Dimension schedules such as (0:15),(2:10),(4:7): subspace dimension and iterations at it.

use crate::LpcaError;

/// (dimension, iterations) pairs, run in order.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Schedule(pub Vec<(usize, usize)>);

/// Iterations allowed at one dimension: far more than LPCA needs to settle, few enough
/// that a typo cannot make a run that never ends.
pub const MAX_ITERATIONS: usize = 10_000;

impl Default for Schedule {
    /// Seed 003's: 0:15,2:10,4:7,8:5,12:4,16:2,24:1.
    fn default() -> Self {
        Schedule(vec![
            (0, 15),
            (2, 10),
            (4, 7),
            (8, 5),
            (12, 4),
            (16, 2),
            (24, 1),
        ])
    }
}

impl std::fmt::Display for Schedule {
    /// As [`Schedule::parse`] reads it: "0:15,2:10,4:7".
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let parts: Vec<String> = self.0.iter().map(|(d, i)| format!("{d}:{i}")).collect();
        f.write_str(&parts.join(","))
    }
}

impl Schedule {
    /// Parses "0:15,2:10,4:7" (parentheses allowed: "(0:15),(2:10)").
    pub fn parse(s: &str) -> Result<Schedule, LpcaError> {
        let bad = |part: &str| {
            LpcaError::Input(format!(
                "bad schedule entry '{part}' in '{s}': expected DIM:ITERATIONS, e.g. 0:15,2:10"
            ))
        };
        let mut out = Vec::new();
        for part in s
            .split(',')
            .map(|p| p.trim().trim_start_matches('(').trim_end_matches(')'))
            .filter(|p| !p.is_empty())
        {
            let (dim, iters) = part.split_once(':').ok_or_else(|| bad(part))?;
            let dim: usize = dim.trim().parse().map_err(|_| bad(part))?;
            let iters: usize = iters.trim().parse().map_err(|_| bad(part))?;
            if iters == 0 {
                return Err(bad(part));
            }
            if iters > MAX_ITERATIONS {
                return Err(LpcaError::Input(format!(
                    "schedule entry '{part}': at most {MAX_ITERATIONS} iterations per dimension (LPCA settles in tens)"
                )));
            }
            out.push((dim, iters));
        }
        if out.is_empty() {
            return Err(LpcaError::Input("the schedule is empty".into()));
        }
        Ok(Schedule(out))
    }

    /// The largest dimension.
    pub fn max_dim(&self) -> usize {
        self.0.iter().map(|s| s.0).max().unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_is_seed_003s_schedule_and_reads_back() {
        let d = Schedule::default();
        assert_eq!(d.to_string(), "0:15,2:10,4:7,8:5,12:4,16:2,24:1");
        assert_eq!(Schedule::parse(&d.to_string()).expect("parses"), d);
        for a in [crate::Algorithm::Lpca, crate::Algorithm::ScLpca] {
            assert_eq!(a.to_string().parse::<crate::Algorithm>(), Ok(a));
        }
        use crate::init::Init;
        for i in [
            Init::Random,
            Init::DistanceSum,
            Init::KmeansPlusPlus,
            Init::SortMeansPlusPlus,
        ] {
            assert_eq!(i.to_string().parse::<Init>(), Ok(i));
        }
    }

    #[test]
    fn parses_the_seed_schedule() {
        let s = Schedule::parse("(0:15),(2:10),(4:7),(8:5),(12:4),(16:2),(24:1)").expect("valid");
        assert_eq!(s.0[0], (0, 15));
        assert_eq!(s.max_dim(), 24);
        assert_eq!(Schedule::parse("0:3").expect("valid").0, vec![(0, 3)]);
        assert!(Schedule::parse("0:0").is_err());
        assert!(Schedule::parse("a:1").is_err());
        assert!(Schedule::parse("").is_err());
        let e = Schedule::parse("0:99999999999").expect_err("endless");
        assert!(e.to_string().contains("at most 10000 iterations"), "{e}");
    }
}
