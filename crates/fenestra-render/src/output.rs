//! Writing a render: linear EXR with metadata, tone-mapped PNG beside it, JSON sidecar.

use crate::film::Film;
use crate::film_file::{self, FilmHeader};
use fenestra_core::fs::{FileSet, WriteError};
use fenestra_core::image::{ExrLayer, Image, ImageError};
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

/// The EXR layers that hold the denoising features: `albedo` (R, G, B) and `normal`
/// (X, Y, Z).
pub fn feature_layers<'a>(albedo: &'a Image, normal: &'a Image) -> [ExrLayer<'a>; 2] {
    [
        ExrLayer {
            name: "albedo",
            channels: ["R", "G", "B"],
            image: albedo,
        },
        ExrLayer {
            name: "normal",
            channels: ["X", "Y", "Z"],
            image: normal,
        },
    ]
}

/// The film-state file written beside OUT.exr by pieces of a split render: OUT.film.
pub fn film_state_path(exr_path: &Path) -> PathBuf {
    exr_path.with_extension("film")
}

/// The variance image written beside OUT.exr: OUT.var.exr.
pub fn variance_path(exr_path: &Path) -> PathBuf {
    exr_path.with_extension("var.exr")
}

/// What light paths brought, written beside OUT.exr with the variance image by renders that
/// trace them: OUT.light-paths.exr (its variance of the mean as the layer `variance`) and
/// its picture OUT.light-paths.png.
pub fn light_paths_path(exr_path: &Path) -> PathBuf {
    exr_path.with_extension("light-paths.exr")
}

/// Where a render's denoising features go.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FeatureLayout {
    /// Into OUT.exr, as its layers `albedo` (R, G, B) and `normal` (X, Y, Z).
    #[default]
    Layers,
    /// Beside it, as plain RGB images OUT.albedo.exr and OUT.normal.exr (normal's X, Y, Z
    /// as R, G, B), for tools that read one image a file (OIDN's oidnDenoise, Blender's image
    /// loader); OUT.exr then holds the picture alone.
    Files,
}

impl FeatureLayout {
    /// Its name: `layers` or `files`.
    pub fn name(self) -> &'static str {
        match self {
            FeatureLayout::Layers => "layers",
            FeatureLayout::Files => "files",
        }
    }
}

impl std::str::FromStr for FeatureLayout {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match [FeatureLayout::Layers, FeatureLayout::Files]
            .into_iter()
            .find(|l| l.name() == s)
        {
            Some(layout) => Ok(layout),
            None => Err(format!(
                "'{s}': layers (the EXR's own layers) or files (OUT.albedo.exr, OUT.normal.exr)"
            )),
        }
    }
}

/// The feature images written beside OUT.exr with [`FeatureLayout::Files`]: (albedo, normal).
pub fn feature_paths(exr_path: &Path) -> (PathBuf, PathBuf) {
    (
        exr_path.with_extension("albedo.exr"),
        exr_path.with_extension("normal.exr"),
    )
}

/// What a render writes beside OUT.exr, OUT.png and OUT.json.
#[derive(Clone, Copy, Debug, Default)]
pub struct Extras<'a> {
    /// Where the film's denoising features go, if it takes them.
    pub features: FeatureLayout,
    /// The PNG's exposure in stops (`None`: automatic).
    pub exposure: Option<f32>,
    /// OUT.var.exr, the per-pixel variance of the mean (and, where light paths were
    /// traced, OUT.light-paths.exr and .png).
    pub variance: bool,
    /// OUT.film, the film's exact accumulators, with this header.
    pub state: Option<&'a FilmHeader>,
    /// OUT.denoised.exr and OUT.denoised.png: this image, the film's denoised.
    pub denoised: Option<&'a Image>,
}

/// The denoised image written beside OUT.exr: OUT.denoised.exr (its PNG OUT.denoised.png).
pub fn denoised_path(exr_path: &Path) -> PathBuf {
    exr_path.with_extension("denoised.exr")
}

/// Writes OUT.exr (with the film's denoising features where `extras` says, if it takes
/// them), OUT.png, the JSON sidecar OUT.json (the statistics) and the `extras`: as
/// one set, so that a failure or an interruption leaves the previous files of the set as
/// they were.
pub fn write_render(
    exr_path: &Path,
    film: &Film,
    stats: &RenderStats,
    extras: &Extras,
) -> Result<(), ImageError> {
    let image = film.image();
    let metadata = exr_metadata(stats);
    let mut set = FileSet::new();
    let features = film.feature_images();
    let layers = match (&features, extras.features) {
        (Some((albedo, normal)), FeatureLayout::Layers) => feature_layers(albedo, normal).to_vec(),
        _ => Vec::new(),
    };
    set.stage(exr_path, |tmp| {
        image.write_exr_layers_to(tmp, &layers, &metadata)
    })?;
    if let (Some((albedo, normal)), FeatureLayout::Files) = (&features, extras.features) {
        let (a, n) = feature_paths(exr_path);
        set.stage(&a, |tmp| albedo.write_exr_to(tmp, &metadata))?;
        set.stage(&n, |tmp| normal.write_exr_to(tmp, &metadata))?;
    }
    // At the image's exposure, so that the pictures beside it compare.
    let exposure = (extras.exposure).unwrap_or(image.auto_exposure_scale().log2());
    if extras.variance {
        let var = film.variance_image();
        set.stage(&variance_path(exr_path), |tmp| {
            var.write_exr_to(tmp, &metadata)
        })?;
        if let Some((light, variance)) = film.light_path_images() {
            let exr = light_paths_path(exr_path);
            let layer = ExrLayer {
                name: "variance",
                channels: ["R", "G", "B"],
                image: &variance,
            };
            set.stage(&exr, |tmp| {
                light.write_exr_layers_to(tmp, &[layer], &metadata)
            })?;
            let png = exr.with_extension("png");
            set.stage(&png, |tmp| light.write_png_to(tmp, Some(exposure)))?;
        }
    }
    if let Some(header) = extras.state {
        set.stage(&film_state_path(exr_path), |tmp| {
            film_file::write(tmp, header, film)
        })?;
    }
    let (png, json) = companion_paths(exr_path);
    set.stage(&png, |tmp| image.write_png_to(tmp, extras.exposure))?;
    if let Some(denoised) = extras.denoised {
        let exr = denoised_path(exr_path);
        set.stage(&exr, |tmp| denoised.write_exr_to(tmp, &metadata))?;
        let png = exr.with_extension("png");
        set.stage(&png, |tmp| denoised.write_png_to(tmp, Some(exposure)))?;
    }
    let text = serde_json::to_string_pretty(stats).map_err(|e| WriteError::new(&json, e))?;
    set.stage(&json, |tmp| std::fs::write(tmp, text + "\n"))?;
    set.commit()?;
    if extras.variance && film.light_paths == 0 {
        // An earlier render's light paths do not belong beside this one.
        let exr = light_paths_path(exr_path);
        let _ = std::fs::remove_file(exr.with_extension("png"));
        let _ = std::fs::remove_file(exr);
    }
    Ok(())
}
