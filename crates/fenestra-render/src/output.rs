//! Writing a render: linear EXR with metadata, tone-mapped PNG beside it, JSON sidecar.

use crate::film::Film;
use crate::film_file::{self, FilmHeader};
use fenestra_core::fs::{FileSet, WriteError};
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
    if !stats.scene_content.is_empty() {
        put("scene_content", stats.scene_content.clone());
    }
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

/// The film-state file written beside OUT.exr by pieces of a split render: OUT.film.
pub fn film_state_path(exr_path: &Path) -> PathBuf {
    exr_path.with_extension("film")
}

/// The variance image written beside OUT.exr: OUT.var.exr.
pub fn variance_path(exr_path: &Path) -> PathBuf {
    exr_path.with_extension("var.exr")
}

/// Writes OUT.exr, OUT.png and the JSON sidecar OUT.json (the statistics), with `variance`
/// OUT.var.exr, the per-pixel variance of the mean, and with `state` OUT.film, the film's
/// exact accumulators: as one set, so that a failure or an interruption leaves the previous
/// files of the set as they were.
pub fn write_render(
    exr_path: &Path,
    film: &Film,
    stats: &RenderStats,
    exposure: Option<f32>,
    variance: bool,
    state: Option<&FilmHeader>,
) -> Result<(), ImageError> {
    let image = film.image();
    let metadata = exr_metadata(stats);
    let mut set = FileSet::new();
    set.stage(exr_path, |tmp| image.write_exr_to(tmp, &metadata))?;
    if variance {
        let var = film.variance_image();
        set.stage(&variance_path(exr_path), |tmp| {
            var.write_exr_to(tmp, &metadata)
        })?;
    }
    if let Some(header) = state {
        set.stage(&film_state_path(exr_path), |tmp| {
            film_file::write(tmp, header, film)
        })?;
    }
    let (png, json) = companion_paths(exr_path);
    set.stage(&png, |tmp| image.write_png_to(tmp, exposure))?;
    let text = serde_json::to_string_pretty(stats).map_err(|e| WriteError::new(&json, e))?;
    set.stage(&json, |tmp| std::fs::write(tmp, text + "\n"))?;
    Ok(set.commit()?)
}
