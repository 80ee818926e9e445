//! Writing a render: linear EXR with metadata, tone-mapped PNG beside it, JSON sidecar.

use crate::film::Film;
use fenestra_core::fs::write_text_atomically;
use fenestra_core::image::ImageError;
use fenestra_core::stats::RenderStats;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The files a render produces for `exr_path`: (png, json).
pub fn companion_paths(exr_path: &Path) -> (PathBuf, PathBuf) {
    (
        exr_path.with_extension("png"),
        exr_path.with_extension("json"),
    )
}

/// EXR header attributes from the render statistics.
pub fn exr_metadata(stats: &RenderStats) -> BTreeMap<String, String> {
    let mut m = BTreeMap::new();
    let mut put = |k: &str, v: String| {
        m.insert(format!("fenestra:{k}"), v);
    };
    put("scene", stats.scene.clone());
    put("integrator", stats.integrator.clone());
    put("spp", stats.spp.to_string());
    put("seed", stats.seed.to_string());
    if let Some(depth) = stats.max_depth {
        put("max_depth", depth.to_string());
    }
    put("render_time_s", format!("{:.6}", stats.time_s));
    put("camera_rays", stats.rays.camera.to_string());
    put("bounce_rays", stats.rays.bounce.to_string());
    put("shadow_rays", stats.rays.shadow.to_string());
    put("dropped_samples", stats.rays.dropped.to_string());
    put("backend", stats.backend.clone());
    put("version", env!("CARGO_PKG_VERSION").to_string());
    m
}

/// The variance image written beside OUT.exr: OUT.var.exr.
pub fn variance_path(exr_path: &Path) -> PathBuf {
    exr_path.with_extension("var.exr")
}

/// Writes OUT.exr, OUT.png and the JSON sidecar OUT.json (the statistics), each atomically;
/// with `variance`, also OUT.var.exr, the per-pixel variance of the mean.
pub fn write_render(
    exr_path: &Path,
    film: &Film,
    stats: &RenderStats,
    exposure: Option<f32>,
    variance: bool,
) -> Result<(), ImageError> {
    let image = film.image();
    image.write_exr(exr_path, &exr_metadata(stats))?;
    if variance {
        film.variance_image()
            .write_exr(&variance_path(exr_path), &exr_metadata(stats))?;
    }
    let (png, json) = companion_paths(exr_path);
    image.write_png(&png, exposure)?;
    let text = serde_json::to_string_pretty(stats)
        .map_err(|e| fenestra_core::fs::WriteError::new(&json, e))?;
    Ok(write_text_atomically(&json, &(text + "\n"))?)
}
