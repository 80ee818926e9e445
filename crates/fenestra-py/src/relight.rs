//! `fenestra.relight`: a precomputation of `fenestra relight precompute` opened once and its
//! frames relit under lights given as data (the lights file's JSON), as `fenestra relight
//! render` relights them.

use crate::error;
use crate::pixels::bytes;
use fenestra_relight::lights_file::LightsFile;
use fenestra_relight::player::Player;
use fenestra_session::relight::{open as open_store, Opened};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::path::PathBuf;
use std::sync::Mutex;

/// An opened precomputation, ready to relight its frames.
#[pyclass(frozen, module = "fenestra._native")]
pub struct Relighter {
    player: Mutex<Player>,
    /// The precomputation's own lights.
    lights: LightsFile,
    frames: u32,
    pool: rayon::ThreadPool,
}

#[pymethods]
impl Relighter {
    /// Frames in the sequence.
    #[getter]
    fn frames(&self) -> u32 {
        self.frames
    }

    /// The precomputation's own lights, as its lights file's JSON.
    fn lights_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.lights).map_err(|e| error(e.into()))
    }

    /// Frame `frame` relit under `lights` (a lights file's JSON; default its own): (float32
    /// RGB bytes, width, height, seconds).
    #[pyo3(signature = (frame, lights=None, indirect_only=false))]
    fn relight<'py>(
        &self,
        py: Python<'py>,
        frame: u32,
        lights: Option<String>,
        indirect_only: bool,
    ) -> PyResult<(Bound<'py, PyBytes>, u32, u32, f64)> {
        let lights = match lights {
            Some(text) => LightsFile::parse(&text, "lights").map_err(|e| error(e.into()))?,
            None => self.lights.clone(),
        };
        let relit = py
            .detach(|| {
                let mut guard = self.player.lock().map_err(|_| {
                    anyhow::anyhow!("an earlier relighting of this precomputation failed")
                })?;
                let player: &mut Player = &mut guard;
                anyhow::Ok(self.pool.install(|| player.relight(frame, &lights))?)
            })
            .map_err(error)?;
        let image = relit.image(indirect_only);
        Ok((bytes(py, &image)?, relit.width, relit.height, relit.seconds))
    }
}

/// Opens the precomputation in `dir` to relight it with `light_samples` samples per area
/// light, on `threads` workers (all cores by default).
#[pyfunction]
#[pyo3(signature = (dir, *, light_samples=16, threads=None))]
pub fn open(
    py: Python<'_>,
    dir: PathBuf,
    light_samples: u32,
    threads: Option<usize>,
) -> PyResult<Relighter> {
    let run = || -> anyhow::Result<Relighter> {
        let Opened {
            store,
            animated,
            lights,
            warnings,
            ..
        } = open_store(&dir, None)?;
        for w in warnings {
            eprintln!("warning: {w}");
        }
        let frames = store.manifest.frames;
        let pool = fenestra_session::thread_pool(threads)?;
        let player = pool.install(|| Player::new(store, animated, light_samples, 0))?;
        Ok(Relighter {
            player: Mutex::new(player),
            lights,
            frames,
            pool,
        })
    };
    py.detach(run).map_err(error)
}
