//! `fenestra.render`: a render through the session's job (the checks, integrator registry,
//! scene build and render loop `fenestra render` runs too), with the interpreter released
//! while it runs, Ctrl-C stopping it with what was rendered kept, and progress polled.

use crate::options::params;
use crate::pixels::{self, bytes};
use crate::progress::watched;
use crate::scene::Scene;
use crate::{backend_named, error, session_error};
use fenestra_core::image::Image;
use fenestra_core::stats::RenderStats;
use fenestra_render::film_file::{FilmHeader, SampleRange};
use fenestra_render::merge::{merge as merge_parts, plan, Part};
use fenestra_render::output::{self, Extras};
use fenestra_render::Film;
use fenestra_session::denoise::{self as denoising, DenoiseMode};
use fenestra_session::files::{
    check_exr, film_file_of, interrupted_path, render_outputs, where_to_write, Beside, Files,
};
use fenestra_session::{registry, Crop, IntegratorChoice, Job, JobSpec, Resolution};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::path::PathBuf;

/// A finished (or interrupted) render: its film and statistics.
#[pyclass(frozen, module = "fenestra._native")]
pub struct Render {
    film: Film,
    stats: RenderStats,
    /// What it was rendered from (scene files, a portals file; a merge's parts): its files
    /// never replace them.
    inputs: Files,
    /// What its film-state file says of it, if it is a piece of a split render.
    piece: Option<FilmHeader>,
    /// Its image denoised, if the render was asked to be (its stats say what denoised it).
    denoised: Option<Image>,
}

#[pymethods]
impl Render {
    /// (width, height) of the film (the crop's, for a cropped render).
    #[getter]
    fn size(&self) -> (u32, u32) {
        (self.film.width, self.film.height)
    }

    /// The image: the mean of each pixel's samples.
    fn pixels<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        bytes(py, &self.film.image())
    }

    /// The per-pixel variance of the mean.
    fn variance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        bytes(py, &self.film.variance_image())
    }

    /// The denoising features (albedo, normal), if the render took them.
    fn features<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<Option<(Bound<'py, PyBytes>, Bound<'py, PyBytes>)>> {
        let Some((albedo, normal)) = self.film.feature_images() else {
            return Ok(None);
        };
        Ok(Some((bytes(py, &albedo)?, bytes(py, &normal)?)))
    }

    /// What light paths brought each pixel, if the render traced any.
    fn light_paths<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyBytes>>> {
        let light = self.film.light_path_images().map(|(light, _)| light);
        light.map(|l| bytes(py, &l)).transpose()
    }

    /// The image denoised, if the render was asked to be.
    fn denoised<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyBytes>>> {
        self.denoised.as_ref().map(|d| bytes(py, d)).transpose()
    }

    /// The statistics, as the JSON sidecar holds them.
    fn stats_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.stats).map_err(|e| error(e.into()))
    }

    /// The one-line summary the command line prints.
    fn summary(&self) -> String {
        self.stats.summary()
    }

    /// Writes `path` (.exr), with the PNG and JSON sidecar beside it (and the variance as
    /// PATH.var.exr if `variance`; a piece of a split render also PATH.film, for `merge`),
    /// as `fenestra render` writes them, atomically; an interrupted render never over a
    /// complete one (it goes to PATH.interrupted.exr), and one stopped before any sample
    /// nowhere. Returns where it went, and the note saying so if that is not `path`.
    #[pyo3(signature = (path, exposure=None, variance=false))]
    fn write(
        &self,
        path: PathBuf,
        exposure: Option<f32>,
        variance: bool,
    ) -> PyResult<(PathBuf, Option<String>)> {
        check_exr(&path).map_err(error)?;
        if self.stats.interrupted && self.stats.spp_max == 0 {
            return Err(error(anyhow::anyhow!(
                "interrupted before any sample: nothing to write"
            )));
        }
        let mut files = self.inputs.clone();
        let piece = self.piece.is_some();
        let beside = Beside {
            variance,
            state: piece,
            denoised: self.denoised.is_some(),
            feature_files: false,
        };
        render_outputs(&mut files, &path, beside);
        render_outputs(&mut files, &interrupted_path(&path), beside)
            .check()
            .map_err(error)?;
        let (to, note) = where_to_write(&path, self.stats.interrupted);
        let extras = Extras {
            exposure,
            variance,
            state: self.piece.as_ref(),
            denoised: self.denoised.as_ref(),
            ..Extras::default()
        };
        output::write_render(&to, &self.film, &self.stats, &extras).map_err(|e| error(e.into()))?;
        Ok((to, note))
    }
}

/// Renders `scene` with `integrator` and `options` (a JSON object of keywords or keys to
/// values), as `fenestra render` does with the same flags. `progress(reading)` is called
/// from the caller's thread as the render goes on; Ctrl-C stops the render and keeps what it
/// has (the statistics say "interrupted").
#[pyfunction]
#[pyo3(signature = (scene, integrator=None, options="{}", *, spp=None, time=None, seed=0, threads=None,
    resolution=None, samples=None, crop=None, backend=None, progress=None, features=false,
    denoise=false, denoise_mode=None))]
#[allow(clippy::too_many_arguments)]
pub fn render(
    py: Python<'_>,
    scene: &Scene,
    integrator: Option<String>,
    options: &str,
    spp: Option<u32>,
    time: Option<f64>,
    seed: u64,
    threads: Option<usize>,
    resolution: Option<(u32, u32)>,
    samples: Option<(u32, u32)>,
    crop: Option<(u32, u32, u32, u32)>,
    backend: Option<String>,
    progress: Option<Py<PyAny>>,
    features: bool,
    denoise: bool,
    denoise_mode: Option<String>,
) -> PyResult<Render> {
    let backend = backend_named(backend.as_deref())?;
    let mode = DenoiseMode::named(denoise_mode.as_deref())
        .map_err(|e| error(anyhow::anyhow!("denoise: {e}")))?;
    let denoise = denoise.then_some(mode);
    if denoise.is_some() {
        denoising::check().map_err(|e| error(e.into()))?;
    }
    let resolution = resolution
        .map(|(w, h)| Resolution::new(w, h))
        .transpose()
        .map_err(session_error)?;
    let spec = JobSpec {
        integrator: IntegratorChoice {
            name: integrator.unwrap_or_else(|| fenestra_session::DEFAULT_INTEGRATOR.to_string()),
            params: params(options, registry().groups()).map_err(error)?,
        },
        spp,
        time,
        seed,
        resolution,
        features: features || denoise.is_some(),
    };
    let mut job = Job::new(scene.loaded.clone(), &spec).map_err(session_error)?;
    let samples = samples.map(|(start, end)| SampleRange { start, end });
    let crop = crop.map(|(x0, y0, x1, y1)| Crop { x0, y0, x1, y1 });
    let inputs = std::mem::take(&mut job.inputs);
    let piece = job.cut(samples, crop, backend).map_err(session_error)?;
    let watched = watched(py, progress.as_ref(), |cancel, polled| {
        job.run(threads, backend, cancel, polled, None, None)
    })?;
    let fenestra_session::Rendered {
        mut stats, film, ..
    } = watched.result.map_err(session_error)?;
    let mut denoised = None;
    if let Some(mode) = denoise.filter(|_| stats.spp_max > 0) {
        let (image, info) = denoising::denoise_film(&film, mode).map_err(|e| error(e.into()))?;
        stats.denoiser = Some(info);
        denoised = Some(image);
    }
    Ok(Render {
        piece: piece.map(|header| FilmHeader {
            stats: stats.clone(),
            ..header
        }),
        film,
        stats,
        inputs,
        denoised,
    })
}

/// `color` (float32 RGB bytes of a `size` image) denoised by OIDN's RT filter as `mode`
/// says (default: the command line's), guided by `albedo` and `normal` (both, or neither) of the same size.
#[pyfunction]
#[pyo3(signature = (color, size, albedo=None, normal=None, mode=None))]
pub fn denoise<'py>(
    py: Python<'py>,
    color: &[u8],
    size: (usize, usize),
    albedo: Option<&[u8]>,
    normal: Option<&[u8]>,
    mode: Option<&str>,
) -> PyResult<Bound<'py, PyBytes>> {
    let mode = DenoiseMode::named(mode).map_err(|e| error(anyhow::anyhow!("mode: {e}")))?;
    let color = pixels::image(color, size).map_err(error)?;
    let guides = match (albedo, normal) {
        (Some(a), Some(n)) => Some((
            pixels::image(a, size).map_err(error)?,
            pixels::image(n, size).map_err(error)?,
        )),
        (None, None) => None,
        _ => {
            return Err(error(anyhow::anyhow!(
                "give both albedo and normal, or neither"
            )))
        }
    };
    let done = py.detach(|| {
        let guides = guides.as_ref().map(|(a, n)| (a, n));
        denoising::denoise(&color, guides, mode)
    });
    let (image, _) = done.map_err(|e| error(e.into()))?;
    bytes(py, &image)
}
/// The pieces of a split render (their .exr or .film files) merged into the render of them
/// all, as `fenestra merge` merges them (`total`: the samples the whole takes, checked).
#[pyfunction]
#[pyo3(signature = (parts, total=None))]
pub fn merge(parts: Vec<PathBuf>, total: Option<u32>) -> PyResult<Render> {
    let run = || -> anyhow::Result<Render> {
        let paths: Vec<PathBuf> = parts.iter().map(|p| film_file_of(p)).collect();
        let mut inputs = Files::default();
        inputs.inputs(&paths, "part");
        let parts = paths
            .iter()
            .map(|p| Part::open(p))
            .collect::<Result<Vec<_>, _>>()?;
        let plan = plan(&parts, total)?;
        let (film, stats) = merge_parts(&parts, &plan)?;
        let piece = FilmHeader {
            key: parts[0].header.key.clone(),
            samples: plan.samples,
            window: plan.window,
            stats: stats.clone(),
            features: film.takes_features(),
        };
        Ok(Render {
            film,
            stats,
            piece: Some(piece),
            inputs,
            denoised: None,
        })
    };
    run().map_err(error)
}
