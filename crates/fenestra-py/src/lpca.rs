//! `fenestra.lpca`: local PCA (seed 003 ch. 3) on NumPy matrices: k-means, SortMeans, LPCA
//! and SortCluster-LPCA as `fenestra lpca` runs them (same defaults), and classification of
//! points to fitted subspaces.

use crate::error;
use fenestra_lpca::classify::full as classify_all;
use fenestra_lpca::{Dataset, Options, Schedule, Subspace};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// Rows of float32 (little-endian bytes, row-major) as a dataset of `(n, d)`.
fn dataset(values: &[u8], (n, d): (usize, usize)) -> anyhow::Result<Dataset> {
    anyhow::ensure!(
        values.len() == n * d * 4,
        "a {n}x{d} matrix needs {} bytes of float32, got {}",
        n * d * 4,
        values.len()
    );
    let values = values
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    Ok(Dataset::new(n, d, values)?)
}

/// Numbers as little-endian bytes.
fn bytes_of<'py, T: Copy, const N: usize>(
    py: Python<'py>,
    values: &[T],
    to: impl Fn(T) -> [u8; N],
) -> PyResult<Bound<'py, PyBytes>> {
    PyBytes::new_with(py, values.len() * N, |out| {
        for (chunk, &v) in out.chunks_exact_mut(N).zip(values) {
            chunk.copy_from_slice(&to(v));
        }
        Ok(())
    })
}

/// A fit: (assignments as u32 bytes, distances as f64 bytes, each subspace's mean and basis
/// as f64 bytes, the run's statistics as JSON).
type Fitted<'py> = (
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Vec<(Bound<'py, PyBytes>, Bound<'py, PyBytes>)>,
    String,
);

/// Subspaces as bytes.
fn models<'py>(
    py: Python<'py>,
    models: &[Subspace],
) -> PyResult<Vec<(Bound<'py, PyBytes>, Bound<'py, PyBytes>)>> {
    models
        .iter()
        .map(|m| {
            let basis: Vec<f64> = m.basis.concat();
            Ok((
                bytes_of(py, &m.mean, f64::to_le_bytes)?,
                bytes_of(py, &basis, f64::to_le_bytes)?,
            ))
        })
        .collect()
}

/// Fits `clusters` local subspaces to the rows of `values` (`shape` = (n, d)).
#[pyfunction]
#[pyo3(signature = (values, shape, clusters, *, schedule=None, algorithm=None, init=None,
    seed=0, threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn fit<'py>(
    py: Python<'py>,
    values: &[u8],
    shape: (usize, usize),
    clusters: usize,
    schedule: Option<String>,
    algorithm: Option<String>,
    init: Option<String>,
    seed: u64,
    threads: Option<usize>,
) -> PyResult<Fitted<'py>> {
    let run = || -> anyhow::Result<_> {
        let data = dataset(values, shape)?;
        let options = Options {
            clusters,
            schedule: schedule
                .as_deref()
                .map_or(Ok(Schedule::default()), Schedule::parse)?,
            algorithm: algorithm
                .as_deref()
                .map_or(Ok(Default::default()), str::parse)?,
            init: init.as_deref().map_or(Ok(Default::default()), str::parse)?,
            seed,
        };
        let pool = fenestra_session::thread_pool(threads)?;
        let outcome = py.detach(|| pool.install(|| fenestra_lpca::run(&data, &options)))?;
        Ok(outcome)
    };
    let outcome = run().map_err(error)?;
    let stats = serde_json::to_string(&outcome).map_err(|e| error(e.into()))?;
    Ok((
        bytes_of(py, &outcome.assignments, u32::to_le_bytes)?,
        bytes_of(py, &outcome.distances, f64::to_le_bytes)?,
        models(py, &outcome.models)?,
        stats,
    ))
}

/// The nearest of the subspaces `(mean, basis)` (f64 bytes; a basis of `dim` rows of d) to
/// each row of `values`: (assignments as u32 bytes, distances as f64 bytes).
#[pyfunction]
pub fn classify<'py>(
    py: Python<'py>,
    values: &[u8],
    shape: (usize, usize),
    subspaces: Vec<(Vec<f64>, Vec<f64>)>,
) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>)> {
    let (n, d) = shape;
    let data = dataset(values, shape).map_err(error)?;
    let mut models = Vec::with_capacity(subspaces.len());
    for (k, (mean, basis)) in subspaces.into_iter().enumerate() {
        if mean.len() != d || basis.len() % d != 0 {
            return Err(error(anyhow::anyhow!(
                "subspace {k}: a mean of {} and a basis of {} numbers do not fit rows of {d}",
                mean.len(),
                basis.len()
            )));
        }
        let basis = basis.chunks_exact(d).map(<[f64]>::to_vec).collect();
        models.push(Subspace { mean, basis });
    }
    if models.is_empty() {
        return Err(error(anyhow::anyhow!("no subspace to classify to")));
    }
    let (mut assign, mut dist) = (vec![0u32; n], vec![0.0f64; n]);
    py.detach(|| classify_all(&data, &models, &mut assign, &mut dist));
    Ok((
        bytes_of(py, &assign, u32::to_le_bytes)?,
        bytes_of(py, &dist, f64::to_le_bytes)?,
    ))
}
