//! `fenestra bench`: runs a suite and writes its report folder.

use anyhow::{bail, Context, Result};
use clap::Args;
use fenestra_eval::report::{aggregate, markdown_table, write_report};
use fenestra_eval::run::{Runner, SuiteOutcome};
use fenestra_eval::suite::{slug, Suite};
use std::path::PathBuf;

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
}

/// Runs the suite; `Ok(true)` when it was interrupted (the report holds what finished).
pub fn run(args: BenchArgs) -> Result<bool> {
    let suite = Suite::load(&args.suite)?;
    let out = args
        .output
        .unwrap_or_else(|| PathBuf::from("bench-out").join(slug(&suite.name)));
    let suite_dir = args.suite.parent().map(PathBuf::from).unwrap_or_default();
    let mut files = crate::files::Files::default();
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
    let runner = Runner {
        program: std::env::current_exe().context("cannot find the fenestra executable")?,
        suite: &suite,
        suite_dir,
        out: out.clone(),
        cache: args.cache,
        threads: args.threads,
    };
    let outcome = if args.report_only {
        let records = fenestra_eval::run::read_results(&out.join("results.jsonl"))?;
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
        let stop = crate::interrupt::on_ctrl_c("reporting the runs that finished");
        runner.run_all(&stop, |msg| eprintln!("{msg}"))?
    };
    write_report(&out, &suite, &outcome.references, &outcome.records)?;
    print!("{}", markdown_table(&aggregate(&suite, &outcome.records)));
    println!("report: {}", out.join("index.html").display());
    if outcome.interrupted {
        eprintln!("interrupted; run the same command again to resume");
        return Ok(true);
    }
    if !outcome.failed.is_empty() {
        let ids: Vec<&str> = outcome.failed.iter().map(|f| f.0.as_str()).collect();
        bail!(
            "{} of {} runs failed ({}); the report shows the others, and running the suite again retries them",
            ids.len(),
            suite.runs().len(),
            ids.join(", ")
        );
    }
    Ok(false)
}
