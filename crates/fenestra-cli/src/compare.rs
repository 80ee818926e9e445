//! `fenestra compare`: error of images against a reference, with efficiency from their
//! sidecars.

use anyhow::{Context, Result};
use clap::Args;
use fenestra_core::image::Image;
use fenestra_core::stats::RenderStats;
use fenestra_eval::metrics;
use serde_json::{json, Value};
use std::path::PathBuf;

#[derive(Args)]
pub struct CompareArgs {
    /// The reference image (EXR or HDR).
    #[arg(long = "ref")]
    reference: PathBuf,
    /// Images to compare (their JSON sidecars, if present, give time and rays).
    #[arg(required = true)]
    images: Vec<PathBuf>,
    /// Print a JSON array, one object per image.
    #[arg(long)]
    json: bool,
}

pub fn run(args: CompareArgs) -> Result<()> {
    let reference = Image::read(&args.reference)?;
    let mut rows = Vec::new();
    for path in &args.images {
        let img = Image::read(path)?;
        let m = metrics::compare(&img, &reference)
            .with_context(|| format!("comparing {}", path.display()))?;
        // The sidecar is optional: images from other renderers have none.
        let sidecar: Option<RenderStats> = std::fs::read_to_string(path.with_extension("json"))
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok());
        let time_s = sidecar.as_ref().map(|s| s.time_s);
        rows.push(json!({
            "image": path, "mse": m.mse, "rel_mse": m.rel_mse, "mae": m.mae, "mean": m.mean,
            "ref_mean": m.ref_mean, "time_s": time_s, "efficiency": time_s.map(|t| metrics::efficiency(m.mse, t)),
            "shadow_rays_per_pixel": sidecar.as_ref().map(|s| s.shadow_rays_per_pixel),
            "spp": sidecar.as_ref().map(|s| s.spp),
        }));
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(());
    }
    println!(
        "{:<40} {:>11} {:>11} {:>11} {:>11} {:>9} {:>11}",
        "image", "MSE", "relMSE", "MAE", "mean", "time s", "efficiency"
    );
    let opt = |v: &Value, digits: usize| {
        v.as_f64()
            .map_or("-".to_string(), |x| format!("{x:.digits$e}"))
    };
    for r in &rows {
        println!(
            "{:<40} {:>11} {:>11} {:>11} {:>11} {:>9} {:>11}",
            r["image"].as_str().unwrap_or("?"),
            opt(&r["mse"], 3),
            opt(&r["rel_mse"], 3),
            opt(&r["mae"], 3),
            opt(&r["mean"], 3),
            r["time_s"]
                .as_f64()
                .map_or("-".to_string(), |t| format!("{t:.2}")),
            opt(&r["efficiency"], 3)
        );
    }
    Ok(())
}
