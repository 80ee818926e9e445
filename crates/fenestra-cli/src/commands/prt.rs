//! `fenestra prt`: precomputed radiance transfer matrices for the LPCA experiments of seed
//! 003 §3.6.1 (fenestra_relight::prt), written as NPY.

use crate::support::progress::Bar;
use anyhow::{bail, Result};
use clap::Args;
use fenestra_relight::prt::{knot_transfer, PrtOptions};
use std::path::PathBuf;

#[derive(Args)]
pub struct PrtArgs {
    /// Segments along the (2,3) torus knot of the procedural mesh.
    #[arg(long, default_value_t = 512)]
    segments: usize,
    /// Vertices around the knot's tube (vertices = segments x sides).
    #[arg(long, default_value_t = 64)]
    sides: usize,
    /// Cubemap face resolution R (columns = 6 R^2).
    #[arg(long, default_value_t = 32)]
    resolution: usize,
    /// Supersampling S x S per cubemap pixel.
    #[arg(long, default_value_t = 4)]
    supersample: usize,
    /// Phong lobe exponent of the glossy material.
    #[arg(long, default_value_t = 20.0)]
    exponent: f32,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Output NPY (float32, vertices x 6 R^2).
    #[arg(short, long)]
    output: PathBuf,
}

pub fn run(args: PrtArgs) -> Result<()> {
    let options = PrtOptions {
        segments: args.segments,
        sides: args.sides,
        resolution: args.resolution,
        supersample: args.supersample,
        exponent: args.exponent,
    };
    let gib = options.bytes() / (1u64 << 30) as f64;
    if gib > 8.0 {
        bail!("the matrix would take {gib:.1} GiB; lower --segments, --sides or --resolution");
    }
    let bar = Bar::new(false);
    let matrix = crate::thread_pool(args.threads)?.install(|| knot_transfer(&options, &bar))?;
    bar.finish();
    let shape = [matrix.rows as u64, matrix.columns as u64];
    fenestra_lpca::io::write_npy(&args.output, &shape, matrix.values)?;
    println!(
        "wrote {} ({} vertices x {} cubemap pixels)",
        args.output.display(),
        matrix.rows,
        matrix.columns
    );
    Ok(())
}
