//! `fenestra.portals.estimate`: automatic light portals (seed 000 ch. 4) as `fenestra portals`
//! estimates them, with its flags as keywords, returned as the portals.json document and the
//! photons and clusters behind it.

use crate::pixels::points;
use crate::progress::watched;
use crate::scene::Scene;
use crate::{backend_named, error};
use fenestra_cli::commands::portals::EstimateOpts;
use fenestra_portals::estimate::estimate as estimate_portals;
use fenestra_render::RenderScene;
use fenestra_scene::Scene as Built;
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// What an estimate found: (portals.json as text, the photons as float32 xyz bytes, each
/// cluster's photon indices, the one-line summary).
type Found<'py> = (String, Bound<'py, PyBytes>, Vec<Vec<usize>>, String);

/// Estimates `scene`'s portals with `fenestra portals`'s flags `flags` ("--theta", "3",
/// ...). Ctrl-C stops it and raises KeyboardInterrupt (part of the photons would give other
/// portals).
#[pyfunction]
#[pyo3(signature = (scene, flags, *, threads=None, backend=None, progress=None))]
pub fn estimate<'py>(
    py: Python<'py>,
    scene: &Scene,
    flags: Vec<String>,
    threads: Option<usize>,
    backend: Option<String>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Found<'py>> {
    #[derive(clap::Parser)]
    #[command(name = "fenestra.portals.estimate", no_binary_name = true)]
    struct Flags {
        #[command(flatten)]
        opts: EstimateOpts,
    }
    let opts = <Flags as clap::Parser>::try_parse_from(&flags)
        .map_err(|e| error(anyhow::anyhow!("{}", e.render().to_string().trim_end())))?
        .opts;
    let params = opts.params();
    let backend = backend_named(backend.as_deref())?;
    let pool = fenestra_cli::thread_pool(threads).map_err(error)?;
    let desc = scene.desc.clone();
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
    let file = serde_json::to_string_pretty(&e.file(&scene.source, &params))
        .map_err(|e| error(e.into()))?;
    Ok((
        file,
        points(py, &e.photons.points)?,
        e.clusters.clone(),
        e.summary(),
    ))
}
