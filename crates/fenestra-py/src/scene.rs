//! `fenestra.load`: a scene read as `fenestra render` reads its SCENE argument.

use crate::error;
use fenestra_cli::support::scene_arg::{self, SceneOptions, SKY_ALBEDO, SKY_TURBIDITY};
use fenestra_scene::SceneDesc;
use pyo3::prelude::*;
use std::path::PathBuf;

/// A loaded scene: rendered as many times as asked, each render from its own copy.
#[pyclass(frozen, module = "fenestra._native")]
pub struct Scene {
    /// What it was loaded from (`builtin:NAME` or a path).
    #[pyo3(get)]
    pub source: String,
    pub desc: SceneDesc,
    /// Every file read, in order: the scene's content hash is theirs.
    pub files: Vec<PathBuf>,
    /// What the scene asks for that fenestra replaces or leaves out.
    #[pyo3(get)]
    warnings: Vec<String>,
    /// A glTF scene's cameras by name.
    #[pyo3(get)]
    cameras: Vec<String>,
}

#[pymethods]
impl Scene {
    /// The scene's name.
    #[getter]
    fn name(&self) -> &str {
        &self.desc.name
    }

    /// The image size its file asks for: (width, height).
    #[getter]
    fn resolution(&self) -> (u32, u32) {
        (self.desc.defaults.width, self.desc.defaults.height)
    }

    /// The samples per pixel its file asks for.
    #[getter]
    fn spp(&self) -> u32 {
        self.desc.defaults.spp
    }

    fn __repr__(&self) -> String {
        let (w, h) = self.resolution();
        format!(
            "<fenestra.Scene '{}' from {}: {} shapes, {} lights, {w}x{h}, {} spp>",
            self.desc.name,
            self.source,
            self.desc.shapes.len(),
            self.desc.lights.len(),
            self.desc.defaults.spp
        )
    }
}

/// Two numbers as the command line writes them: "A,B".
fn pair(p: Option<(f64, f64)>) -> Option<String> {
    p.map(|(a, b)| format!("{a},{b}"))
}

/// Loads `source` (`builtin:NAME`, a pbrt-v4, glTF 2.0, OBJ or PLY file) as `fenestra
/// render` does with the same flags (the keywords are its scene flags).
#[pyfunction]
#[pyo3(signature = (source, *, strict=false, environment=None, sky=false, sky_turbidity=None,
    sky_albedo=None, sun=None, sun_time=None, location=None, sun_strength=None,
    environment_rotation=None,
    environment_strength=None, environment_up=None, camera=None))]
#[allow(clippy::too_many_arguments)]
pub fn load(
    py: Python<'_>,
    source: String,
    strict: bool,
    environment: Option<PathBuf>,
    sky: bool,
    sky_turbidity: Option<f32>,
    sky_albedo: Option<f32>,
    sun: Option<(f64, f64)>,
    sun_time: Option<String>,
    location: Option<(f64, f64)>,
    sun_strength: Option<f32>,
    environment_rotation: Option<f32>,
    environment_strength: Option<f32>,
    environment_up: Option<String>,
    camera: Option<String>,
) -> PyResult<Scene> {
    let needs_sky = [
        ("sky_turbidity", sky_turbidity.is_some()),
        ("sky_albedo", sky_albedo.is_some()),
        ("sun", sun.is_some()),
        ("sun_time", sun_time.is_some()),
        ("sun_strength", sun_strength.is_some()),
    ];
    if let Some((word, _)) = needs_sky.iter().find(|(_, given)| *given && !sky) {
        return Err(error(anyhow::anyhow!(
            "{word} describes sky=True's sky; sky is not set"
        )));
    }
    if environment.is_some() && sky {
        return Err(error(anyhow::anyhow!(
            "environment and sky both light the scene: give one"
        )));
    }
    if sun.is_some() && sun_time.is_some() {
        return Err(error(anyhow::anyhow!(
            "sun and sun_time both place the sun: give one"
        )));
    }
    if sun_time.is_some() != location.is_some() {
        return Err(error(anyhow::anyhow!(
            "sun_time and location go together: the sun at that moment seen from there"
        )));
    }
    let options = SceneOptions {
        strict,
        environment,
        sky,
        sky_turbidity: sky_turbidity.unwrap_or(SKY_TURBIDITY),
        sky_albedo: sky_albedo.unwrap_or(SKY_ALBEDO),
        sun: pair(sun),
        sun_time,
        location: pair(location),
        sun_strength,
        environment_rotation,
        environment_strength,
        environment_up,
        camera,
    };
    let loaded = py
        .detach(|| scene_arg::load_quietly(&source, &options))
        .map_err(error)?;
    Ok(Scene {
        warnings: loaded.warnings(),
        cameras: loaded.cameras,
        source,
        desc: loaded.desc,
        files: loaded.files,
    })
}
