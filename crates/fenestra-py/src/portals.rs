//! `fenestra.portals.estimate`: automatic light portals (seed 000 ch. 4) as `fenestra portals`
//! estimates them, the estimator's options group as keywords, returned as the portals.json
//! document and the photons and clusters behind it.

use crate::options::params;
use crate::pixels::points;
use crate::progress::watched;
use crate::scene::Scene;
use crate::{backend_named, error, session_error};
use fenestra_portals::estimate::estimate as estimate_portals;
use fenestra_portals::EstimateOptions;
use fenestra_render::options::Options;
use fenestra_render::RenderScene;
use fenestra_scene::Scene as Built;
use fenestra_session::error::option_name_in;
use fenestra_session::Style;
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::path::PathBuf;

/// What an estimate found: (portals.json as text, the photons as float32 xyz bytes, each
/// cluster's photon indices, the one-line summary).
type Found<'py> = (String, Bound<'py, PyBytes>, Vec<Vec<usize>>, String);

/// Estimates `scene`'s portals with the estimator's options `options` (a JSON object of
/// keywords, `fenestra portals`'s flags with underscores: {"theta": 3, ...}). Ctrl-C stops it
/// and raises KeyboardInterrupt (part of the photons would give other portals).
#[pyfunction]
#[pyo3(signature = (scene, options="{}", *, threads=None, backend=None, progress=None))]
pub fn estimate<'py>(
    py: Python<'py>,
    scene: &Scene,
    options: &str,
    threads: Option<usize>,
    backend: Option<String>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Found<'py>> {
    let groups = [EstimateOptions::unprefixed_group()];
    let given = params(options, &groups).map_err(error)?;
    let params = EstimateOptions::from_params(&given)
        .map_err(|e| {
            let word = option_name_in(&e.key, &groups, Style::Keyword);
            error(anyhow::anyhow!(
                "{}{e}",
                word.map_or_else(String::new, |w| format!("{w}: "))
            ))
        })?
        .params();
    let backend = backend_named(backend.as_deref())?;
    let pool = fenestra_session::thread_pool(threads).map_err(session_error)?;
    let desc = scene.loaded.desc.clone();
    let watched = watched(py, progress.as_ref(), |cancel, polled| {
        pool.install(|| -> anyhow::Result<_> {
            let built = RenderScene::new(Built::build(desc, backend)?);
            Ok(estimate_portals(&built, &params, cancel, polled)?)
        })
    })?;
    if watched.interrupted {
        return Err(PyKeyboardInterrupt::new_err(
            "portal estimation interrupted",
        ));
    }
    let e = watched.result.map_err(error)?;
    let file = serde_json::to_string_pretty(&e.file(&scene.loaded.source, &params))
        .map_err(|e| error(e.into()))?;
    Ok((
        file,
        points(py, &e.photons.points)?,
        e.clusters.clone(),
        e.summary(),
    ))
}

/// Writes an estimate's portals.json `text` to `path` under the rules of `fenestra portals`'s
/// output: not over a file of `scene` (its scene file, textures, meshes), in a folder made if
/// missing, whole or not at all.
#[pyfunction]
pub fn write_portals(scene: &Scene, text: &str, path: PathBuf) -> PyResult<()> {
    let mut files = fenestra_session::files::Files::default();
    files
        .inputs(&scene.loaded.files, "scene file")
        .output(&path, "portals file");
    fenestra_session::files::create_output_folder(&path).map_err(error)?;
    files.check().map_err(error)?;
    fenestra_core::fs::write_text_atomically(&path, text).map_err(|e| error(e.into()))
}
