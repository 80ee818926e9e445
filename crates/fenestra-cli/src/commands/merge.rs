//! `fenestra merge`: the pieces of a split render (sample ranges, tiles) into one image, the
//! one a single render of them all makes, bit for bit.

use crate::support::denoise::DenoiseArgs;
use anyhow::{bail, Result};
use clap::Args;
use fenestra_render::film_file::FilmHeader;
use fenestra_render::merge::{self, Part};
use fenestra_render::output::{self, Extras};
use fenestra_session::files::{check_exr, film_file_of, render_outputs, Beside, Files};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Args)]
pub struct MergeArgs {
    /// The parts: film-state files (OUT.film) that `fenestra render --samples` or `--crop`
    /// wrote, or their EXRs (the .film beside each is read). Any order.
    #[arg(required = true)]
    parts: Vec<PathBuf>,
    /// Check that the parts hold samples 0 to N-1 of every pixel, and say which are
    /// missing if they do not.
    #[arg(long, value_name = "N")]
    total: Option<u32>,
    /// Accept parts that together cover only a rectangle of the image (a crop): the output
    /// is that rectangle. Without it such parts are refused, so that a missing tile is not
    /// merged into an image with a hole cut off.
    #[arg(long)]
    partial: bool,
    /// Also write OUT.var.exr, the per-pixel variance of the mean.
    #[arg(long)]
    variance: bool,
    /// PNG exposure in stops (default: automatic).
    #[arg(long, allow_negative_numbers = true)]
    exposure: Option<f32>,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    denoise: DenoiseArgs,
    /// Output EXR; the PNG, the JSON sidecar and OUT.film (to merge further) go beside it.
    #[arg(short, long)]
    output: PathBuf,
}

/// Checks the parts, merges them and writes the image; nothing is written unless every part
/// is whole and they belong together.
pub fn run(args: MergeArgs) -> Result<()> {
    let started = Instant::now();
    check_exr(&args.output)?;
    let paths: Vec<PathBuf> = args.parts.iter().map(|p| film_file_of(p)).collect();
    let mut files = Files::default();
    files.inputs(&paths, "part");
    let beside = Beside {
        variance: args.variance,
        state: true,
        denoised: args.denoise.denoise.is_some(),
        feature_files: false,
    };
    render_outputs(&mut files, &args.output, beside).check()?;
    args.denoise.check()?;
    let parts = paths
        .iter()
        .map(|p| Part::open(p))
        .collect::<Result<Vec<_>, _>>()?;
    let plan = merge::plan(&parts, args.total)?;
    let w = plan.window;
    if !args.partial && (w.width(), w.height()) != (w.full_width, w.full_height) {
        bail!(
            "the parts cover pixels {w} of a {}x{} image: merge the missing tiles too, or pass \
             --partial to write that rectangle alone",
            w.full_width,
            w.full_height
        );
    }
    let (film, mut stats) = merge::merge(&parts, &plan)?;
    let denoised = args.denoise.apply(&film, &mut stats)?;
    let header = FilmHeader {
        key: parts[0].header.key.clone(),
        samples: plan.samples,
        window: plan.window,
        stats: stats.clone(),
        features: film.takes_features(),
    };
    let extras = Extras {
        exposure: args.exposure,
        variance: args.variance,
        state: Some(&header),
        denoised: denoised.as_ref(),
        ..Extras::default()
    };
    output::write_render(&args.output, &film, &stats, &extras)?;
    if args.json {
        println!("{}", serde_json::to_string(&stats)?);
    } else {
        let samples = plan
            .samples
            .map_or_else(|| "adaptive".to_string(), |s| format!("samples {s}"));
        println!(
            "merged {} parts ({samples}, pixels {} of {}x{}) into {} in {:.2} s",
            parts.len(),
            plan.window,
            plan.window.full_width,
            plan.window.full_height,
            args.output.display(),
            started.elapsed().as_secs_f64()
        );
    }
    Ok(())
}
