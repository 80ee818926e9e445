//! `fenestra lpca` (compress a matrix with local PCA) and `fenestra btf` (the synthetic
//! BTF-like data of seed 003 §3.6.2).

use anyhow::{bail, Result};
use clap::Args;
use fenestra_lpca::init::Init;
use fenestra_lpca::{io, synthetic, Algorithm, Options, Schedule};
use serde_json::json;
use std::path::PathBuf;

#[derive(Args)]
pub struct LpcaArgs {
    /// A 2D float32/float64 NPY matrix, one data point per row.
    data: PathBuf,
    /// Number of clusters k.
    #[arg(long)]
    clusters: usize,
    /// Subspace dimensions and iterations, e.g. "0:15,2:10,4:7,8:5,12:4,16:2,24:1";
    /// "0:N" alone is k-means.
    #[arg(long, default_value_t = Schedule::default().to_string())]
    schedule: String,
    /// lpca (exhaustive; Lloyd for 0:N) or sc-lpca (SortCluster-LPCA; SortMeans for 0:N).
    #[arg(long, default_value_t)]
    algorithm: Algorithm,
    /// random, distance-sum, kmeans++ or sortmeans++.
    #[arg(long, default_value_t)]
    init: Init,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Output folder: assignments.npy, means.npy, bases.npy, dims.npy, coefficients.npy,
    /// stats.json.
    #[arg(short, long)]
    output: PathBuf,
}

pub fn run(args: LpcaArgs) -> Result<()> {
    fenestra_session::files::Files::default()
        .input(&args.data, "data")
        .folder(&args.output, "output folder")
        .check()?;
    let schedule = Schedule::parse(&args.schedule)?;
    let data = io::read_matrix(&args.data)?;
    let options = Options {
        clusters: args.clusters,
        schedule,
        algorithm: args.algorithm,
        init: args.init,
        seed: args.seed,
    };
    let pool = crate::thread_pool(args.threads)?;
    let outcome = pool.install(|| fenestra_lpca::run(&data, &options))?;
    let stats = json!({
        "data": args.data, "rows": data.n, "dimension": data.d, "clusters": args.clusters,
        "schedule": options.schedule, "algorithm": options.algorithm, "init_method": options.init, "seed": args.seed,
        "threads": pool.current_num_threads(), "outcome": outcome,
    });
    io::write_model(&args.output, &data, &outcome, &stats)?;
    eprintln!(
        "{} rows x {}: {} clusters, phi {:.6e}, relative squared error {:.4e}; classification {:.2} s, {} distances; seeding {:.2} s ({} distances)",
        data.n,
        data.d,
        args.clusters,
        outcome.phi,
        outcome.relative_squared_error,
        outcome.classification_seconds,
        outcome.distance_evals,
        outcome.init.seconds,
        outcome.init.distance_evals
    );
    println!("wrote {}", args.output.display());
    Ok(())
}

#[derive(Args)]
pub struct BtfArgs {
    /// Texture size (rows = size^2 texels).
    #[arg(long, default_value_t = 128)]
    size: usize,
    /// View directions.
    #[arg(long, default_value_t = 16)]
    views: usize,
    /// Light directions (columns = views x lights).
    #[arg(long, default_value_t = 16)]
    lights: usize,
    #[arg(long, default_value_t = 32)]
    materials: usize,
    /// Dimension of each material's family of apparent BRDFs.
    #[arg(long, default_value_t = 8)]
    dim: usize,
    #[arg(long, default_value_t = 0.01)]
    noise: f64,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Output NPY file (float32, rows x columns).
    #[arg(short, long)]
    output: PathBuf,
}

pub fn btf(args: BtfArgs) -> Result<()> {
    if args.size == 0 || args.views == 0 || args.lights == 0 || args.materials == 0 {
        bail!("--size, --views, --lights and --materials must be positive");
    }
    if !(args.noise.is_finite() && args.noise >= 0.0) {
        bail!(
            "--noise must be a finite non-negative number, got {}",
            args.noise
        );
    }
    let (rows, columns) = (
        args.size.saturating_mul(args.size),
        args.views.saturating_mul(args.lights),
    );
    if args.materials > rows || args.dim > columns {
        bail!(
            "--materials ({}) can be at most the {rows} texels and --dim ({}) at most the {columns} columns",
            args.materials,
            args.dim
        );
    }
    let bytes = (args.size as f64).powi(2) * args.views as f64 * args.lights as f64 * 8.0;
    if bytes > 8.0 * (1u64 << 30) as f64 {
        bail!(
            "the matrix would take {:.1} GiB; lower --size, --views or --lights",
            bytes / (1u64 << 30) as f64
        );
    }
    let data = synthetic::btf_like(
        args.size,
        args.views,
        args.lights,
        args.materials,
        args.dim,
        args.noise,
        args.seed,
    );
    io::write_npy(
        &args.output,
        &[data.n as u64, data.d as u64],
        data.values.iter().copied(),
    )?;
    println!("wrote {} ({} x {})", args.output.display(), data.n, data.d);
    Ok(())
}
