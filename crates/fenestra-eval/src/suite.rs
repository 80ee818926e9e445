//! Bench suites: which scenes, techniques and budgets to compare, read from TOML.

use crate::EvalError;
use fenestra_core::fs::slug;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A bench suite (TOML): scenes x techniques x budgets x repetitions.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Suite {
    /// Its name (the report folder's by default).
    pub name: String,
    /// What it measures.
    #[serde(default)]
    pub description: String,
    /// Image size [width, height] for every run.
    pub resolution: [u32; 2],
    /// Runs of each configuration, with seeds seed, seed + 1, ...
    #[serde(default = "one")]
    pub repetitions: u32,
    /// Seed of the first repetition.
    #[serde(default)]
    pub seed: u64,
    /// How references are rendered.
    pub reference: Reference,
    /// The scenes and path lengths.
    #[serde(rename = "scene")]
    pub scenes: Vec<SceneEntry>,
    /// The first technique is the baseline that speed-ups are relative to.
    #[serde(rename = "technique")]
    pub techniques: Vec<Technique>,
    /// The budgets every technique gets.
    #[serde(rename = "budget")]
    pub budgets: Vec<Budget>,
}

fn one() -> u32 {
    1
}

/// How references are rendered.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Reference {
    /// The integrator.
    pub integrator: String,
    /// Samples per pixel.
    pub spp: u32,
    /// More `fenestra render` arguments for the reference.
    #[serde(default)]
    pub args: Vec<String>,
}

/// A scene and its path lengths.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SceneEntry {
    /// builtin:NAME or a scene file (relative to the suite file).
    pub scene: String,
    /// Path lengths to run (segments, 2 = direct light).
    pub max_depth: Vec<u32>,
    /// More `fenestra render` arguments for this scene, its reference's and every
    /// technique's, e.g. ["--sky"] for a glTF interior.
    #[serde(default)]
    pub args: Vec<String>,
}

/// A way of rendering: an integrator with options.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Technique {
    /// Its name in tables and plots.
    pub label: String,
    /// The integrator.
    pub integrator: String,
    /// More `fenestra render` arguments, e.g. ["--mis", "balance"].
    #[serde(default)]
    pub args: Vec<String>,
    /// Whether the integrator decides each pixel's samples itself (ias): a samples budget is
    /// then not passed to it (it would refuse it); a time budget is.
    #[serde(default)]
    pub adaptive: bool,
}

impl Technique {
    /// The `fenestra render` arguments that impose `budget` on this technique.
    pub fn budget_args(&self, budget: &Budget) -> Vec<String> {
        match budget.spp {
            Some(_) if self.adaptive => Vec::new(),
            _ => budget.render_args(),
        }
    }
}

/// Exactly one of `spp`, `time` or `rel_mse` (time to reach a relative MSE, within
/// `max_time`).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Budget {
    /// Equal samples per pixel.
    pub spp: Option<u32>,
    /// Equal time, in seconds.
    pub time: Option<f64>,
    /// Equal quality: render until this relative MSE.
    pub rel_mse: Option<f64>,
    /// With `rel_mse`: give up after this many seconds.
    pub max_time: Option<f64>,
}

impl Budget {
    /// Short name used in run ids and tables.
    pub fn label(&self) -> String {
        match (self.spp, self.time, self.rel_mse) {
            (Some(s), _, _) => format!("{s}spp"),
            (_, Some(t), _) => format!("{t}s"),
            (_, _, Some(r)) => format!("relmse{r}"),
            _ => "invalid".into(),
        }
    }

    /// The `fenestra render` arguments that impose the budget.
    pub fn render_args(&self) -> Vec<String> {
        match (self.spp, self.time, self.rel_mse) {
            (Some(s), _, _) => vec!["--spp".into(), s.to_string()],
            (_, Some(t), _) => vec!["--time".into(), t.to_string()],
            (_, _, Some(r)) => {
                vec![
                    "--target-rel-mse".into(),
                    r.to_string(),
                    "--time".into(),
                    self.max_time.unwrap_or(600.0).to_string(),
                ]
            }
            _ => vec![],
        }
    }
}

/// One render of a suite.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct RunSpec {
    /// A hash of everything that changes the run's result (resolution, the technique's
    /// integrator and arguments, the budget, seed, scene, path length, the reference, the
    /// version): resuming reuses a recorded run only when its key matches.
    #[serde(default)]
    pub key: String,
    /// Unique name (the image's file name).
    pub id: String,
    /// The scene.
    pub scene: String,
    /// Path length.
    pub max_depth: u32,
    /// Index of the technique.
    pub technique: usize,
    /// Index of the budget.
    pub budget: usize,
    /// Repetition, from 0.
    pub repetition: u32,
    /// Seed of its sample streams.
    pub seed: u64,
}

impl Suite {
    /// Reads and checks a suite file; errors name the file, line and column.
    pub fn load(path: &Path) -> Result<Suite, EvalError> {
        let bad = |reason: String| EvalError::Suite {
            path: path.display().to_string(),
            reason,
        };
        let text = std::fs::read_to_string(path).map_err(|e| bad(format!("cannot read: {e}")))?;
        let suite: Suite = toml::from_str(&text).map_err(|e| {
            let (line, col) = e.span().map_or((0, 0), |s| line_col(&text, s.start));
            EvalError::Suite {
                path: format!("{}:{line}:{col}", path.display()),
                reason: e.message().to_string(),
            }
        })?;
        suite.check().map_err(|problem| bad(problem.to_string()))?;
        Ok(suite)
    }

    fn check(&self) -> Result<(), SuiteProblem> {
        if self.scenes.is_empty() || self.techniques.is_empty() || self.budgets.is_empty() {
            return Err(SuiteProblem::Empty);
        }
        if self.resolution.contains(&0) || self.repetitions == 0 || self.reference.spp == 0 {
            return Err(SuiteProblem::NotPositive);
        }
        for (i, b) in self.budgets.iter().enumerate() {
            let budget = i + 1;
            let set = [b.spp.is_some(), b.time.is_some(), b.rel_mse.is_some()]
                .iter()
                .filter(|&&x| x)
                .count();
            if set != 1 {
                return Err(SuiteProblem::BudgetKind { budget });
            }
            if b.max_time.is_some() && b.rel_mse.is_none() {
                return Err(SuiteProblem::MaxTime { budget });
            }
            let positive = |x: Option<f64>| x.is_none_or(|x| x.is_finite() && x > 0.0);
            if b.spp == Some(0) || ![b.time, b.rel_mse, b.max_time].into_iter().all(positive) {
                return Err(SuiteProblem::BudgetValue { budget });
            }
        }
        // Run ids (and so file names) are built from these names: they must stay distinct.
        distinct(
            self.techniques.iter().map(|t| slug(&t.label)),
            "technique labels",
        )?;
        distinct(self.scenes.iter().map(|s| slug(&s.scene)), "scenes")?;
        distinct(self.budgets.iter().map(Budget::label), "budgets")?;
        for s in &self.scenes {
            if s.max_depth.is_empty() || s.max_depth.contains(&0) {
                return Err(SuiteProblem::MaxDepth {
                    scene: s.scene.clone(),
                });
            }
        }
        Ok(())
    }

    /// Every run, in the order they are executed.
    pub fn runs(&self) -> Vec<RunSpec> {
        let mut runs = Vec::new();
        for s in &self.scenes {
            for &d in &s.max_depth {
                for (b, budget) in self.budgets.iter().enumerate() {
                    // Repetition by repetition, the techniques in turn: a machine whose
                    // speed drifts over minutes then slows them all alike.
                    for rep in 0..self.repetitions {
                        for (t, tech) in self.techniques.iter().enumerate() {
                            let id = format!(
                                "{}-d{d}-{}-{}-r{rep}",
                                slug(&s.scene),
                                slug(&tech.label),
                                budget.label()
                            );
                            let seed = self.seed + rep as u64;
                            let key = fenestra_core::hash::debug_hash(&(
                                self.resolution,
                                (&tech.integrator, &tech.args),
                                tech.budget_args(budget),
                                seed,
                                (&s.scene, &s.args, d),
                                (&self.reference.integrator, self.reference.spp),
                                &self.reference.args,
                                env!("CARGO_PKG_VERSION"),
                            ));
                            runs.push(RunSpec {
                                key: format!("{key:016x}"),
                                id,
                                scene: s.scene.clone(),
                                max_depth: d,
                                technique: t,
                                budget: b,
                                repetition: rep,
                                seed,
                            });
                        }
                    }
                }
            }
        }
        runs
    }
}

/// Refuses names that coincide (after `slug`), naming the first pair.
fn distinct(names: impl Iterator<Item = String>, what: &'static str) -> Result<(), SuiteProblem> {
    let mut seen = std::collections::HashSet::new();
    for n in names {
        if !seen.insert(n.clone()) {
            return Err(SuiteProblem::SameName { what, name: n });
        }
    }
    Ok(())
}

/// What makes a suite that parses unusable.
#[derive(Debug, thiserror::Error)]
enum SuiteProblem {
    #[error("a suite needs at least one [[scene]], [[technique]] and [[budget]]")]
    Empty,
    #[error("resolution, repetitions and reference spp must be positive")]
    NotPositive,
    #[error("budget {budget}: give exactly one of spp, time or rel_mse")]
    BudgetKind { budget: usize },
    #[error("budget {budget}: max_time goes with rel_mse")]
    MaxTime { budget: usize },
    #[error("budget {budget}: spp, time, rel_mse and max_time must be positive and finite")]
    BudgetValue { budget: usize },
    #[error("{what} must give distinct file names; two give \"{name}\"")]
    SameName { what: &'static str, name: String },
    #[error("scene {scene}: max_depth needs path lengths of at least 1")]
    MaxDepth { scene: String },
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, col)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SUITE: &str = r#"
name = "t"
resolution = [8, 8]
repetitions = 2
[reference]
integrator = "af_hf"
spp = 64
[[scene]]
scene = "builtin:box-hole"
max_depth = [2, 4]
[[technique]]
label = "HF"
integrator = "hf"
[[technique]]
label = "AF_HF power"
integrator = "af_hf"
args = ["--mis", "power"]
[[budget]]
spp = 4
[[budget]]
rel_mse = 0.1
max_time = 5
"#;

    fn write(name: &str, text: &str) -> std::path::PathBuf {
        let p =
            std::env::temp_dir().join(format!("fenestra-suite-{}-{name}.toml", std::process::id()));
        std::fs::write(&p, text).expect("write");
        p
    }

    #[test]
    fn suites_expand_into_runs() {
        let s = Suite::load(&write("ok", SUITE)).expect("valid");
        let runs = s.runs();
        assert_eq!(runs.len(), 2 * 2 * 2 * 2);
        assert_eq!(runs[0].id, "box-hole-d2-hf-4spp-r0");
        // The techniques alternate within a repetition.
        assert_eq!(runs[1].id, "box-hole-d2-af_hf_power-4spp-r0");
        assert_eq!((runs[1].seed, runs[2].seed), (0, 1));
        assert_eq!(
            s.budgets[1].render_args(),
            ["--target-rel-mse", "0.1", "--time", "5"]
        );
        let mut ids: Vec<_> = runs.iter().map(|r| r.id.clone()).collect();
        ids.dedup();
        assert_eq!(ids.len(), runs.len(), "ids are unique");
    }

    #[test]
    fn adaptive_techniques_take_time_budgets_and_no_sample_counts() {
        let text = SUITE.replace(
            "label = \"HF\"\nintegrator = \"hf\"",
            "label = \"IAS\"\nintegrator = \"ias\"\nadaptive = true",
        );
        let s = Suite::load(&write("adaptive", &text)).expect("valid");
        let (ias, af_hf) = (&s.techniques[0], &s.techniques[1]);
        assert!(ias.adaptive && !af_hf.adaptive);
        assert!(ias.budget_args(&s.budgets[0]).is_empty());
        assert_eq!(af_hf.budget_args(&s.budgets[0]), ["--spp", "4"]);
        assert_eq!(ias.budget_args(&s.budgets[1]), s.budgets[1].render_args());
    }

    #[test]
    fn bad_suites_are_explained() {
        let e = Suite::load(&write("typo", &SUITE.replace("repetitions", "repetitons")))
            .unwrap_err()
            .to_string();
        assert!(e.contains(":4:1:") && e.contains("repetitons"), "{e}");
        let e = Suite::load(&write(
            "two",
            &SUITE.replace("spp = 4\n", "spp = 4\ntime = 2\n"),
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("budget 1: give exactly one"), "{e}");
        let e = Suite::load(&write("depth", &SUITE.replace("[2, 4]", "[]")))
            .unwrap_err()
            .to_string();
        assert!(e.contains("max_depth"), "{e}");
        let e = Suite::load(Path::new("/no/suite.toml"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/no/suite.toml: cannot read"), "{e}");
        // Labels that differ only in characters a file name cannot hold would share files.
        let e = Suite::load(&write(
            "labels",
            &SUITE
                .replace("\"HF\"", "\"H F\"")
                .replace("\"AF_HF power\"", "\"H/F\""),
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("two give \"h_f\""), "{e}");
        for bad in ["spp = 0", "time = -1.0", "time = nan", "time = inf"] {
            let e = Suite::load(&write("budget", &SUITE.replace("spp = 4", bad)))
                .unwrap_err()
                .to_string();
            assert!(e.contains("must be positive and finite"), "{bad}: {e}");
        }
    }

    #[test]
    fn a_run_is_keyed_by_everything_that_changes_its_result() {
        let key = |text: &str| {
            Suite::load(&write("key", text)).expect("valid").runs()[0]
                .key
                .clone()
        };
        let base = key(SUITE);
        assert_eq!(base, key(SUITE), "the same suite, the same key");
        for changed in [
            SUITE.replace("[8, 8]", "[8, 16]"),
            SUITE.replace("integrator = \"hf\"", "integrator = \"af_hf\""),
            SUITE.replace("spp = 64", "spp = 32"),
            SUITE.replace("repetitions = 2", "repetitions = 2\nseed = 5"),
            SUITE.replace(
                "max_depth = [2, 4]",
                "max_depth = [2, 4]\nargs = [\"--sky\"]",
            ),
        ] {
            assert_ne!(key(&changed), base, "{changed}");
        }
    }
}
