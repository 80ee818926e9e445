//! `fenestra compare`: error of images against a reference, with efficiency from their
//! sidecars.

use anyhow::{bail, Context, Result};
use clap::Args;
use fenestra_core::image::{read_exr_metadata, Image};
use fenestra_core::stats::RenderStats;
use fenestra_eval::colormap::write_error_map;
use fenestra_eval::metrics;
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

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
    /// Compare only the pixels where this image (EXR, same size; a work map of `render
    /// --maps` such as sdrc's cached.exr) exceeds 0.5 in its first channel; the region error
    /// stays over the whole image.
    #[arg(long)]
    mask: Option<PathBuf>,
    /// Compare images smaller than the reference by a whole factor against the reference
    /// averaged over blocks of that factor (a box filter): a reference rendered larger.
    #[arg(long)]
    downsample: bool,
    /// Also write IMAGE.error.png beside each image: its per-pixel relative squared error
    /// (luminance) against the reference, on bench reports' log scale (1e-4 black to 10 pale
    /// yellow).
    #[arg(long)]
    error_maps: bool,
}

/// The reference at `image`'s size: itself, or with `--downsample` averaged over blocks
/// when it is a whole multiple of the image's size.
fn reference_for<'a>(
    reference: &'a Image,
    image: &Image,
    path: &Path,
    args: &CompareArgs,
) -> Result<std::borrow::Cow<'a, Image>> {
    let (w, h, rw, rh) = (image.width, image.height, reference.width, reference.height);
    if (w, h) == (rw, rh) {
        return Ok(std::borrow::Cow::Borrowed(reference));
    }
    let factor = (w > 0 && rw % w == 0 && rh % h.max(1) == 0 && rw / w == rh / h.max(1))
        .then_some(rw / w.max(1));
    match factor {
        Some(k) if args.downsample && args.mask.is_none() => {
            Ok(std::borrow::Cow::Owned(reference.downsampled(k)))
        }
        Some(_) if args.downsample => {
            bail!("--mask is at the reference's size: not with --downsample ({} is {w}x{h}, the reference {rw}x{rh})", path.display())
        }
        Some(k) => bail!(
            "{} is {w}x{h}, the reference {rw}x{rh} ({k} times larger): add --downsample to average the reference over {k}x{k} blocks",
            path.display()
        ),
        None => bail!(
            "{} is {w}x{h}, the reference {rw}x{rh}, not a whole multiple of it",
            path.display()
        ),
    }
}

/// fenestra's EXR attributes of an image (none for other files and other renderers').
fn attributes(path: &Path) -> BTreeMap<String, String> {
    read_exr_metadata(path).unwrap_or_default()
}

/// Refuses an image of another scene than the reference's, and warns when both were
/// rendered with one seed: they share random numbers, which understates the error.
fn check_pair(
    image: &Path,
    reference: &Path,
    ref_attributes: &BTreeMap<String, String>,
) -> Result<()> {
    let attributes = attributes(image);
    let both = |key: &str| Some((attributes.get(key)?, ref_attributes.get(key)?));
    if let Some((scene, ref_scene)) = both("fenestra:scene").filter(|(a, b)| a != b) {
        bail!(
            "{} is an image of scene '{scene}' and the reference {} of scene '{ref_scene}'",
            image.display(),
            reference.display()
        );
    }
    // Scenes of one name (every scene-v4.pbrt of Bitterli's set) differ in content.
    if let Some((content, ref_content)) = both("fenestra:scene_content").filter(|(a, b)| a != b) {
        let name = attributes.get("fenestra:scene").map_or("", String::as_str);
        bail!(
            "{} is an image of another scene than the reference {}: their scenes' contents differ ({content}, {ref_content}) though both are named '{name}'",
            image.display(),
            reference.display()
        );
    }
    if let Some((seed, _)) = both("fenestra:seed").filter(|(a, b)| a == b) {
        eprintln!(
            "warning: {} and the reference were both rendered with seed {seed}: they share \
             random numbers, so the error is understated (`fenestra reference` renders in a \
             seed space of its own)",
            image.display()
        );
    }
    Ok(())
}

pub fn run(args: CompareArgs) -> Result<()> {
    let reference = Image::read(&args.reference)?;
    let ref_attributes = attributes(&args.reference);
    let mask = match &args.mask {
        None => None,
        Some(path) => {
            let m = Image::read(path)?;
            if (m.width, m.height) != (reference.width, reference.height) {
                bail!(
                    "the mask {} is {}x{}, the reference {}x{}",
                    path.display(),
                    m.width,
                    m.height,
                    reference.width,
                    reference.height
                );
            }
            let keep: Vec<bool> = m.pixels.iter().map(|p| p.r > 0.5).collect();
            if !keep.contains(&true) {
                bail!("the mask {} selects no pixel", path.display());
            }
            Some(keep)
        }
    };
    let mut rows = Vec::new();
    for path in &args.images {
        let img = Image::read(path)?;
        check_pair(path, &args.reference, &ref_attributes)?;
        let reference = reference_for(&reference, &img, path, &args)?;
        let m = metrics::compare_where(&img, &reference, mask.as_deref())
            .with_context(|| format!("comparing {}", path.display()))?;
        if args.error_maps {
            write_error_map(&img, &reference, &path.with_extension("error.png"))?;
        }
        // The sidecar is optional: images from other renderers have none.
        let sidecar: Option<RenderStats> = std::fs::read_to_string(path.with_extension("json"))
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok());
        let time_s = sidecar.as_ref().map(|s| s.time_s);
        rows.push(json!({
            "image": path, "mse": m.mse, "rel_mse": m.rel_mse, "mae": m.mae, "mean": m.mean,
            "ref_mean": m.ref_mean, "region_error": m.region_error, "worst_share": m.worst_share, "time_s": time_s, "efficiency": time_s.map(|t| metrics::efficiency(m.mse, t)),
            "shadow_rays_per_pixel": sidecar.as_ref().map(|s| s.shadow_rays_per_pixel),
            "spp": sidecar.as_ref().map(|s| s.spp),
        }));
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(());
    }
    println!(
        "{:<40} {:>11} {:>11} {:>11} {:>11} {:>11} {:>9} {:>9} {:>11}",
        "image", "MSE", "relMSE", "MAE", "mean", "region err", "worst 1%", "time s", "efficiency"
    );
    let opt = |v: &Value, digits: usize| {
        v.as_f64()
            .map_or("-".to_string(), |x| format!("{x:.digits$e}"))
    };
    for r in &rows {
        println!(
            "{:<40} {:>11} {:>11} {:>11} {:>11} {:>11} {:>9} {:>9} {:>11}",
            r["image"].as_str().unwrap_or("?"),
            opt(&r["mse"], 3),
            opt(&r["rel_mse"], 3),
            opt(&r["mae"], 3),
            opt(&r["mean"], 3),
            opt(&r["region_error"], 3),
            r["worst_share"]
                .as_f64()
                .map_or("-".to_string(), |w| format!("{:.1}%", 100.0 * w)),
            r["time_s"]
                .as_f64()
                .map_or("-".to_string(), |t| format!("{t:.2}")),
            opt(&r["efficiency"], 3)
        );
    }
    Ok(())
}
