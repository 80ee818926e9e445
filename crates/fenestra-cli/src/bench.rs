//! `fenestra bench`: runs a suite and writes its report folder.

use anyhow::{Context, Result};
use clap::Args;
use fenestra_eval::report::{aggregate, markdown_table, write_report};
use fenestra_eval::run::Runner;
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

pub fn run(args: BenchArgs) -> Result<()> {
    let suite = Suite::load(&args.suite).map_err(anyhow::Error::msg)?;
    let out = args
        .output
        .unwrap_or_else(|| PathBuf::from("bench-out").join(slug(&suite.name)));
    let runner = Runner {
        program: std::env::current_exe().context("cannot find the fenestra executable")?,
        suite: &suite,
        suite_dir: args.suite.parent().map(PathBuf::from).unwrap_or_default(),
        out: out.clone(),
        cache: args.cache,
        threads: args.threads,
    };
    let (refs, records) = if args.report_only {
        let records = fenestra_eval::run::read_results(&out.join("results.jsonl"))
            .map_err(anyhow::Error::msg)?;
        let mut refs: Vec<_> = records
            .iter()
            .map(|r| fenestra_eval::run::ReferenceRecord {
                scene: r.spec.scene.clone(),
                max_depth: r.spec.max_depth,
                image: r.reference.clone(),
                cached: true,
            })
            .collect();
        refs.sort_by(|a, b| (&a.scene, a.max_depth).cmp(&(&b.scene, b.max_depth)));
        refs.dedup_by(|a, b| a.scene == b.scene && a.max_depth == b.max_depth);
        (refs, records)
    } else {
        runner
            .run_all(|msg| eprintln!("{msg}"))
            .map_err(anyhow::Error::msg)?
    };
    write_report(&out, &suite, &refs, &records)?;
    print!("{}", markdown_table(&aggregate(&suite, &records)));
    println!("report: {}", out.join("index.html").display());
    Ok(())
}
