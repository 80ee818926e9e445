//! fenestra as a Python module (`fenestra._native`, wrapped by the `fenestra` package in
//! `python/`): scenes and renders through the render session the command line stands on too
//! (`fenestra-session`: so an image is the one `fenestra render` makes with the same
//! settings), films as bytes NumPy reads without a copy, and the measurement toolkit's
//! comparisons. Keywords are the command line's flags with underscores, and errors name them.

mod compare;
mod lpca;
mod options;
mod pixels;
mod portals;
mod progress;
mod relight;
mod render;
mod scene;

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    _native,
    FenestraError,
    PyException,
    "An error fenestra reports: bad input (a scene file's file:line:col), a bad option (named by its keyword), an image that cannot be written."
);

/// The error `e` as Python sees it, with the message the command line prints.
fn error(e: anyhow::Error) -> PyErr {
    match e.downcast::<fenestra_session::Error>() {
        Ok(e) => session_error(e),
        Err(e) => FenestraError::new_err(format!("{e:#}")),
    }
}

/// A session's error as Python sees it: settings and options named by their keywords.
fn session_error(e: fenestra_session::Error) -> PyErr {
    FenestraError::new_err(e.worded(fenestra_session::Style::Keyword))
}

/// The ray-query backend called `name` (default: the binary's).
fn backend_named(name: Option<&str>) -> PyResult<fenestra_scene::Backend> {
    name.map_or(Ok(Default::default()), |n| {
        n.parse()
            .map_err(|e| error(anyhow::anyhow!("backend: {e}")))
    })
}

#[pymodule]
#[pyo3(name = "_native")]
fn native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("FenestraError", m.py().get_type::<FenestraError>())?;
    m.add("VERSION", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<render::Render>()?;
    m.add_class::<relight::Relighter>()?;
    m.add_function(wrap_pyfunction!(scene::load, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(render::merge, m)?)?;
    m.add_function(wrap_pyfunction!(render::denoise, m)?)?;
    m.add_function(wrap_pyfunction!(options::options, m)?)?;
    m.add_function(wrap_pyfunction!(portals::estimate, m)?)?;
    m.add_function(wrap_pyfunction!(portals::write_portals, m)?)?;
    m.add_function(wrap_pyfunction!(lpca::fit, m)?)?;
    m.add_function(wrap_pyfunction!(lpca::classify, m)?)?;
    m.add_function(wrap_pyfunction!(relight::open, m)?)?;
    m.add_function(wrap_pyfunction!(compare::compare, m)?)?;
    m.add_function(wrap_pyfunction!(compare::read_image, m)?)?;
    m.add_function(wrap_pyfunction!(compare::read_features, m)?)?;
    m.add_function(wrap_pyfunction!(compare::png, m)?)?;
    Ok(())
}
