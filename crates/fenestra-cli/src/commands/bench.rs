//! `fenestra bench`: runs a suite and writes its report folder.

use crate::support::engine_job::{Engine, EngineJob, Step, PIECE};
use anyhow::{bail, Context, Result};
use clap::Args;
use fenestra_core::fs::slug;
use fenestra_eval::report::{aggregate, markdown_table, write_report};
use fenestra_eval::run::{Runner, SuiteOutcome};
use fenestra_eval::suite::Suite;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct BenchArgs {
    /// The suite (TOML, see bench/core.toml).
    suite: PathBuf,
    /// Report folder (default: bench-out/SUITE_NAME). Running again resumes: finished runs
    /// are kept.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Folder of cached references.
    #[arg(long, default_value = "refs")]
    cache: PathBuf,
    /// Worker threads for each render (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Only write the report from the runs already recorded.
    #[arg(long)]
    report_only: bool,
    /// Run only these runs (ids as in the report, comma-separated), each recorded in a file
    /// of its own (results.d/ID.jsonl), and write no report: the task of a job.
    #[arg(long, value_delimiter = ',', value_name = "ID,...")]
    only: Vec<String>,
    /// Render (or find in the cache) the references of the runs, and no run.
    #[arg(long)]
    references_only: bool,
    /// Write the suite as a job for this engine instead of running it: a step rendering the
    /// references (a task per scene and path length), a step running the runs (a task each)
    /// and a step writing the report.
    #[arg(long, value_enum, requires = "job")]
    engine: Option<Engine>,
    /// The job folder for --engine.
    #[arg(long, requires = "engine")]
    job: Option<PathBuf>,
}

/// Runs the suite; `Ok(true)` when it was interrupted (the report holds what finished).
pub fn run(args: BenchArgs) -> Result<bool> {
    let suite = Suite::load(&args.suite)?;
    let out = args
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("bench-out").join(slug(&suite.name)));
    let suite_dir = args.suite.parent().map(PathBuf::from).unwrap_or_default();
    let mut files = fenestra_session::files::Files::default();
    files
        .input(&args.suite, "suite")
        .folder(&out, "report folder")
        .folder(&args.cache, "reference cache");
    for s in suite
        .scenes
        .iter()
        .filter(|s| !s.scene.starts_with("builtin:"))
    {
        files.input(&suite_dir.join(&s.scene), "scene");
    }
    files.check()?;
    let ids: Vec<String> = suite.runs().into_iter().map(|r| r.id).collect();
    if let Some(unknown) = args.only.iter().find(|id| !ids.contains(id)) {
        bail!(
            "the suite has no run {unknown} (its runs: {})",
            ids.join(", ")
        );
    }
    if let (Some(engine), Some(dir)) = (args.engine, &args.job) {
        return write_job(&args, &suite, &out, engine, dir).map(|_| false);
    }
    let runner = Runner {
        program: std::env::current_exe().context("cannot find the fenestra executable")?,
        suite: &suite,
        suite_dir,
        out: out.clone(),
        cache: args.cache.clone(),
        threads: args.threads,
        only: args.only.clone(),
        references_only: args.references_only,
    };
    let outcome = if args.report_only {
        let records = fenestra_eval::run::read_results(&out)?;
        let mut references: Vec<_> = records
            .iter()
            .map(|r| fenestra_eval::run::ReferenceRecord {
                scene: r.spec.scene.clone(),
                max_depth: r.spec.max_depth,
                image: r.reference.clone(),
                cached: true,
                key: r.reference_key.clone(),
            })
            .collect();
        references.sort_by(|a, b| (&a.scene, a.max_depth).cmp(&(&b.scene, b.max_depth)));
        references.dedup_by(|a, b| a.scene == b.scene && a.max_depth == b.max_depth);
        SuiteOutcome {
            references,
            records,
            failed: Vec::new(),
            interrupted: false,
        }
    } else {
        let stop = crate::support::interrupt::on_ctrl_c("reporting the runs that finished");
        runner.run_all(&stop, |msg| eprintln!("{msg}"))?
    };
    if args.only.is_empty() && !args.references_only {
        write_report(&out, &suite, &outcome.references, &outcome.records)?;
        print!("{}", markdown_table(&aggregate(&suite, &outcome.records)));
        println!("report: {}", out.join("index.html").display());
    }
    if outcome.interrupted {
        eprintln!("interrupted; run the same command again to resume");
        return Ok(true);
    }
    if !outcome.failed.is_empty() {
        let ids: Vec<&str> = outcome.failed.iter().map(|f| f.0.as_str()).collect();
        bail!(
            "{} of {} runs failed ({}); the report shows the others, and running the suite again retries them",
            ids.len(),
            runs_asked(&args, &suite),
            ids.join(", ")
        );
    }
    Ok(false)
}

fn runs_asked(args: &BenchArgs, suite: &Suite) -> usize {
    if args.only.is_empty() {
        suite.runs().len()
    } else {
        args.only.len()
    }
}

/// The suite as a job: references (a task per scene and path length, run before the runs
/// that need them), runs (a task each) and the report.
fn write_job(
    args: &BenchArgs,
    suite: &Suite,
    out: &Path,
    engine: Engine,
    dir: &Path,
) -> Result<()> {
    let absolute = |p: &Path| -> Result<String> {
        Ok(std::path::absolute(p)
            .with_context(|| format!("cannot place {}", p.display()))?
            .display()
            .to_string())
    };
    let mut base = vec![
        "bench".to_string(),
        absolute(&args.suite)?,
        "-o".into(),
        absolute(out)?,
        "--cache".into(),
        absolute(&args.cache)?,
    ];
    if let Some(t) = args.threads {
        base.extend(["--threads".into(), t.to_string()]);
    }
    let runs = suite.runs();
    let mut groups: Vec<((String, u32), Vec<String>)> = Vec::new();
    for r in &runs {
        let key = (r.scene.clone(), r.max_depth);
        match groups.iter_mut().find(|(k, _)| *k == key) {
            Some((_, ids)) => ids.push(r.id.clone()),
            None => groups.push((key, vec![r.id.clone()])),
        }
    }
    let step = |name, extra: &[&str], pieces: Vec<String>| Step {
        name,
        args: base
            .iter()
            .cloned()
            .chain(extra.iter().map(|s| s.to_string()))
            .collect(),
        pieces,
        // Timings compare only when a run has the machine to itself.
        whole_machine: true,
    };
    let job = EngineJob {
        title: format!("bench {} ({} runs)", suite.name, runs.len()),
        fenestra: std::env::current_exe()
            .context("cannot find the fenestra executable")?
            .display()
            .to_string(),
        dir: std::path::absolute(dir)?,
        steps: vec![
            step(
                "References",
                &["--references-only", "--only", PIECE],
                groups.into_iter().map(|(_, ids)| ids.join(",")).collect(),
            ),
            step(
                "Runs",
                &["--only", PIECE],
                runs.iter().map(|r| r.id.clone()).collect(),
            ),
            step("Report", &["--report-only"], Vec::new()),
        ],
    };
    for (path, how) in job.write(engine)? {
        println!("wrote {} ({how})", path.display());
    }
    Ok(())
}
