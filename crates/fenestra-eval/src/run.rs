//! Running a suite: each reference and each run is a separate `fenestra` process, so one
//! technique's crash loses nothing else. Finished runs are appended to `results.jsonl` at
//! once; running the suite again skips them (resume after an interruption). A selection of
//! runs (the task of a job on a farm) records each of its runs in a file of its own,
//! `results.d/ID.jsonl`, so that tasks on many machines never write the same file.

use crate::metrics::{self, Metrics};
use crate::suite::{RunSpec, Suite};
use crate::EvalError;
use fenestra_core::fs::slug;
use fenestra_core::image::Image;
use fenestra_core::stats::RenderStats;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};

/// A finished run: what was asked, what the renderer reported, and its error.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunRecord {
    /// What was asked.
    pub spec: RunSpec,
    /// Path of the EXR relative to the report folder (the denoised one, for a run that
    /// denoised).
    pub image: String,
    /// Path of its reference, relative to the report folder.
    pub reference: String,
    /// The reference's cache key (it hashes the scene's content): a record is reused only
    /// with the same reference.
    #[serde(default)]
    pub reference_key: String,
    /// The render's statistics (its JSON sidecar: time, samples, rays, convergence).
    pub stats: RenderStats,
    /// Its error against the reference.
    pub metrics: Metrics,
}

/// The reference of one (scene, path length).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ReferenceRecord {
    /// The scene.
    pub scene: String,
    /// Path length.
    pub max_depth: u32,
    /// Path relative to the report folder.
    pub image: String,
    /// Found in the cache (false: rendered for this report).
    pub cached: bool,
    /// Its cache key.
    #[serde(default)]
    pub key: String,
}

/// What running a suite produced.
pub struct SuiteOutcome {
    /// The references, by scene and path length.
    pub references: Vec<ReferenceRecord>,
    /// The suite's runs that have a result, in the suite's order.
    pub records: Vec<RunRecord>,
    /// Runs that failed this time: (id, why).
    pub failed: Vec<(String, String)>,
    /// The suite was stopped before its end (the records hold what finished).
    pub interrupted: bool,
}

fn file_error(path: &Path, e: impl std::fmt::Display) -> EvalError {
    EvalError::File {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

/// Added to the seed of `fenestra reference`: references live in a seed space of their own.
pub const REFERENCE_SEED_OFFSET: u64 = 1 << 40;

/// Runs a suite's references and renders as `fenestra` processes.
pub struct Runner<'a> {
    /// The `fenestra` executable.
    pub program: PathBuf,
    /// The suite.
    pub suite: &'a Suite,
    /// Folder of the suite file (scene paths are relative to it).
    pub suite_dir: PathBuf,
    /// The report folder.
    pub out: PathBuf,
    /// Where references are cached across reports.
    pub cache: PathBuf,
    /// Worker threads of each render (all cores by default).
    pub threads: Option<usize>,
    /// Run only these runs (by id; all when empty), recording each in results.d/.
    pub only: Vec<String>,
    /// Render (or find) the selected runs' references, and no run.
    pub references_only: bool,
}

/// What `fenestra reference --json` prints.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ReferenceSummary {
    /// The cached reference image.
    pub path: PathBuf,
    /// Whether it was found in the cache (false: rendered now).
    pub cached: bool,
    /// Its statistics (JSON sidecar).
    pub sidecar: PathBuf,
    /// The cache key: a hash of the scene's content and every setting.
    #[serde(default)]
    pub key: String,
}

/// Runs `cmd` and reads what it prints on stdout as JSON.
fn run_json<T: DeserializeOwned>(mut cmd: Command) -> Result<T, EvalError> {
    let command = format!("{cmd:?}");
    let failed = |reason: String| EvalError::Run {
        command: command.clone(),
        reason,
    };
    let out = cmd.output().map_err(|e| failed(e.to_string()))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(failed(format!("{}: {}", out.status, err.trim())));
    }
    serde_json::from_slice(&out.stdout).map_err(|e| failed(format!("unreadable summary: {e}")))
}

impl Runner<'_> {
    fn scene_arg(&self, scene: &str) -> String {
        if scene.starts_with("builtin:") {
            scene.to_string()
        } else {
            self.suite_dir.join(scene).display().to_string()
        }
    }

    /// `fenestra SUB SCENE` at the suite's resolution and path length `depth`, with the
    /// scene entry's own arguments.
    fn base(&self, sub: &str, scene: &str, depth: u32) -> Command {
        let mut cmd = Command::new(&self.program);
        let [w, h] = self.suite.resolution;
        cmd.args([
            sub,
            &self.scene_arg(scene),
            "--resolution",
            &format!("{w}x{h}"),
            "--max-depth",
            &depth.to_string(),
            "--json",
            "--quiet",
        ]);
        if let Some(t) = self.threads {
            cmd.args(["--threads", &t.to_string()]);
        }
        if let Some(entry) = self.suite.scenes.iter().find(|e| e.scene == scene) {
            cmd.args(&entry.args);
        }
        cmd
    }

    /// Renders (or finds in the cache) the reference of (scene, depth). `fenestra reference`
    /// renders it in a seed space of its own, far from the runs' (seed, seed + 1, ...): a run
    /// sharing the reference's random numbers would look converged.
    pub fn reference(&self, scene: &str, depth: u32) -> Result<ReferenceRecord, EvalError> {
        let r = &self.suite.reference;
        let mut cmd = self.base("reference", scene, depth);
        cmd.args([
            "--integrator",
            &r.integrator,
            "--spp",
            &r.spp.to_string(),
            "--seed",
            &self.suite.seed.to_string(),
        ]);
        cmd.args(["--cache", &self.cache.display().to_string()]);
        cmd.args(&r.args);
        let summary: ReferenceSummary = run_json(cmd)?;
        // Copy it into the report folder so the report stands alone.
        let rel = format!("refs/{}-d{depth}.exr", slug(scene));
        let refs = self.out.join("refs");
        std::fs::create_dir_all(&refs).map_err(|e| file_error(&refs, e))?;
        std::fs::copy(&summary.path, self.out.join(&rel))
            .map_err(|e| file_error(&summary.path, e))?;
        Ok(ReferenceRecord {
            scene: scene.into(),
            max_depth: depth,
            image: rel,
            cached: summary.cached,
            key: summary.key,
        })
    }

    /// Renders one run and measures it against its reference.
    pub fn run(&self, spec: &RunSpec, reference: &ReferenceRecord) -> Result<RunRecord, EvalError> {
        let tech = &self.suite.techniques[spec.technique];
        let rel = format!("runs/{}.exr", spec.id);
        let mut cmd = self.base("render", &spec.scene, spec.max_depth);
        cmd.args([
            "--integrator",
            &tech.integrator,
            "--seed",
            &spec.seed.to_string(),
        ]);
        cmd.args(&tech.args);
        cmd.args(tech.budget_args(&self.suite.budgets[spec.budget]));
        cmd.args([
            "--reference",
            &self.out.join(&reference.image).display().to_string(),
        ]);
        cmd.args(["-o", &self.out.join(&rel).display().to_string()]);
        let stats: RenderStats = run_json(cmd)?;
        // A run asked to denoise (`--denoise` in its technique's arguments) is scored by the
        // picture it is for: its denoised image (OUT.denoised.exr).
        let rel = match stats.denoiser {
            Some(_) => format!("runs/{}.denoised.exr", spec.id),
            None => rel,
        };
        let img = Image::read(&self.out.join(&rel))?;
        let reference_img = Image::read(&self.out.join(&reference.image))?;
        let metrics = metrics::compare(&img, &reference_img)?;
        Ok(RunRecord {
            spec: spec.clone(),
            image: rel,
            reference: reference.image.clone(),
            reference_key: reference.key.clone(),
            stats,
            metrics,
        })
    }

    /// Runs everything not yet in results.jsonl; `report` hears about each step.
    pub fn run_all(
        &self,
        stop: &AtomicBool,
        mut report: impl FnMut(&str),
    ) -> Result<SuiteOutcome, EvalError> {
        let runs_dir = self.out.join("runs");
        std::fs::create_dir_all(&runs_dir).map_err(|e| file_error(&runs_dir, e))?;
        let results_path = self.out.join("results.jsonl");
        let mut done = read_results(&self.out)?;
        let selected = |spec: &RunSpec| self.only.is_empty() || self.only.contains(&spec.id);
        let record = |record: &RunRecord| -> Result<(), EvalError> {
            let line = serde_json::to_string(record).map_err(|e| file_error(&results_path, e))?;
            if self.only.is_empty() {
                let mut file = std::fs::OpenOptions::new()
                    .create(true)
                    .append(true)
                    .open(&results_path)
                    .map_err(|e| file_error(&results_path, e))?;
                file.write_all(format!("{line}\n").as_bytes())
                    .and_then(|_| file.flush())
                    .map_err(|e| file_error(&results_path, e))
            } else {
                let dir = self.out.join("results.d");
                let path = dir.join(format!("{}.jsonl", record.spec.id));
                std::fs::create_dir_all(&dir).map_err(|e| file_error(&dir, e))?;
                fenestra_core::fs::write_text_atomically(&path, &format!("{line}\n"))
                    .map_err(|e| file_error(&path, e))
            }
        };
        let mut references: HashMap<(String, u32), ReferenceRecord> = HashMap::new();
        let runs = self.suite.runs();
        let mut failed = Vec::new();
        let mut interrupted = false;
        let mut reused = 0;
        // A recorded run counts when its settings (spec, with its key) and its reference (whose
        // key hashes the scene's content) are those of this suite now.
        let current = |r: &RunRecord, spec: &RunSpec, reference: &ReferenceRecord| {
            r.spec == *spec && r.reference_key == reference.key
        };
        // A stop request reaches the child being run too (Ctrl-C signals the process group):
        // what it left unfinished is neither recorded nor counted as failed.
        for (i, spec) in runs.iter().enumerate().filter(|(_, s)| selected(s)) {
            if stop.load(Ordering::SeqCst) {
                interrupted = true;
                break;
            }
            let key = (spec.scene.clone(), spec.max_depth);
            if !references.contains_key(&key) {
                report(&format!(
                    "reference {} path length {}",
                    spec.scene, spec.max_depth
                ));
                match self.reference(&spec.scene, spec.max_depth) {
                    Ok(r) => references.insert(key.clone(), r),
                    Err(_) if stop.load(Ordering::SeqCst) => {
                        interrupted = true;
                        break;
                    }
                    Err(e) => return Err(e),
                };
            }
            if self.references_only {
                continue;
            }
            if done.iter().any(|r| current(r, spec, &references[&key])) {
                reused += 1;
                continue;
            }
            report(&format!("[{}/{}] {}", i + 1, runs.len(), spec.id));
            match self.run(spec, &references[&key]) {
                Ok(r) => {
                    record(&r)?;
                    done.push(r);
                }
                Err(_) if stop.load(Ordering::SeqCst) => {
                    interrupted = true;
                    break;
                }
                Err(e) => {
                    report(&format!("run {} failed (the others go on): {e}", spec.id));
                    failed.push((spec.id.clone(), e.to_string()));
                }
            }
        }
        // Runs are reused by their settings and reference alone: say so, since a changed
        // renderer with the same settings would otherwise go unnoticed.
        if reused > 0 {
            report(&format!(
                "{reused} finished runs reused from {} (remove it, and runs/, to render them again with this build)",
                results_path.display()
            ));
        }
        // Only runs of the current suite, in its order (the latest record of each).
        let records = runs
            .iter()
            .filter_map(|s| {
                let reference = references.get(&(s.scene.clone(), s.max_depth))?;
                done.iter()
                    .rev()
                    .find(|r| current(r, s, reference))
                    .cloned()
            })
            .collect();
        let mut refs: Vec<ReferenceRecord> = references.into_values().collect();
        refs.sort_by(|a, b| (&a.scene, a.max_depth).cmp(&(&b.scene, b.max_depth)));
        Ok(SuiteOutcome {
            references: refs,
            records,
            failed,
            interrupted,
        })
    }
}

/// The runs recorded so far in the report folder `out`: results.jsonl, then results.d/ in
/// name order (a truncated last line, from an interrupted write, is ignored).
pub fn read_results(out: &Path) -> Result<Vec<RunRecord>, EvalError> {
    let mut files = vec![out.join("results.jsonl")];
    let dir = out.join("results.d");
    if let Ok(entries) = std::fs::read_dir(&dir) {
        let mut more: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "jsonl"))
            .collect();
        more.sort();
        files.extend(more);
    }
    let mut records = Vec::new();
    for path in files {
        match std::fs::read_to_string(&path) {
            Ok(text) => records.extend(text.lines().filter_map(|l| serde_json::from_str(l).ok())),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(file_error(&path, e)),
        }
    }
    Ok(records)
}
