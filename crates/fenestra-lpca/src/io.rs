//! NPY input and output, and the compressed model written by `fenestra lpca`:
//!
//! | file | shape, type | content |
//! |---|---|---|
//! | `assignments.npy` | (n,) int32 | cluster of every row |
//! | `means.npy` | (k, d) float32 | origin of every cluster's subspace |
//! | `bases.npy` | (k, l, d) float32 | orthonormal directions, zero rows past `dims[j]` |
//! | `dims.npy` | (k,) int32 | dimension of every subspace |
//! | `coefficients.npy` | (n, l) float32 | coordinates of every row in its subspace |
//! | `stats.json` | | per-iteration dimension, seconds and distance evaluations, totals, phi |
//!
//! Row i is reconstructed as `means[a] + sum_m coefficients[i, m] bases[a, m]` with
//! `a = assignments[i]`.

use crate::data::Dataset;
use crate::lpca::Outcome;
use crate::LpcaError;
use fenestra_core::fs::{write_atomically, write_text_atomically};
use npyz::WriterBuilder;
use std::io::{BufReader, BufWriter};
use std::path::Path;

fn err(path: &Path, reason: impl std::fmt::Display) -> LpcaError {
    LpcaError::Io {
        path: path.display().to_string(),
        reason: reason.to_string(),
    }
}

/// A header may claim any shape: before the NPY reader trusts it (for allocation, or a
/// product that overflows), check that the file holds at least one byte per claimed value.
fn check_header(path: &Path) -> Result<(), LpcaError> {
    use std::io::Read;
    let mut head = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(65_536).read_to_end(&mut head))
        .map_err(|e| err(path, e))?;
    let text = String::from_utf8_lossy(&head);
    let Some(shape) = text
        .split_once("'shape':")
        .and_then(|(_, rest)| rest.split_once('('))
        .and_then(|(_, rest)| rest.split_once(')'))
        .map(|(shape, _)| shape)
    else {
        // Not a header we can read: the NPY reader says what is wrong.
        return Ok(());
    };
    let size = std::fs::metadata(path).map_err(|e| err(path, e))?.len();
    let claimed = shape
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .try_fold(1u64, |acc, s| {
            s.parse::<u64>().ok().and_then(|v| acc.checked_mul(v))
        });
    match claimed {
        Some(values) if values <= size => Ok(()),
        _ => Err(err(
            path,
            format!("the header claims the shape ({shape}), more values than the file's {size} bytes hold"),
        )),
    }
}

/// Reads a 2D NPY matrix of float32 or float64 (C or Fortran order) as rows.
pub fn read_matrix(path: &Path) -> Result<Dataset, LpcaError> {
    check_header(path)?;
    let file = std::fs::File::open(path).map_err(|e| err(path, e))?;
    let npy = npyz::NpyFile::new(BufReader::new(file))
        .map_err(|e| err(path, format!("not a NumPy .npy file: {e}")))?;
    let shape = npy.shape().to_vec();
    let [n, d] = shape[..] else {
        return Err(err(
            path,
            format!("expected a 2D matrix (rows of vectors), found shape {shape:?}"),
        ));
    };
    let (n, d) = (n as usize, d as usize);
    let order = npy.order();
    let descr = npy.dtype().descr();
    let values: Vec<f32> = match descr.as_str() {
        "'<f4'" | "<f4" => npy.into_vec::<f32>().map_err(|e| err(path, e))?,
        "'<f8'" | "<f8" => npy
            .into_vec::<f64>()
            .map_err(|e| err(path, e))?
            .into_iter()
            .map(|v| v as f32)
            .collect(),
        other => {
            return Err(err(
                path,
                format!("unsupported element type {other}: expected float32 or float64"),
            ))
        }
    };
    let values = match order {
        npyz::Order::C => values,
        npyz::Order::Fortran => {
            let mut out = vec![0.0f32; n * d];
            for c in 0..d {
                for r in 0..n {
                    out[r * d + c] = values[c * n + r];
                }
            }
            out
        }
    };
    Dataset::new(n, d, values).map_err(|e| err(path, e))
}

/// Writes an array of the given shape atomically (temporary file, then rename).
pub fn write_npy<T: npyz::AutoSerialize>(
    path: &Path,
    shape: &[u64],
    data: impl IntoIterator<Item = T>,
) -> Result<(), LpcaError> {
    let write = |tmp: &Path| -> std::io::Result<()> {
        let file = BufWriter::new(std::fs::File::create(tmp)?);
        let mut w = npyz::WriteOptions::new()
            .default_dtype()
            .shape(shape)
            .writer(file)
            .begin_nd()?;
        w.extend(data)?;
        w.finish()
    };
    write_atomically(path, write).map_err(|e| err(path, e.reason))
}

/// Writes the compressed model and statistics into `dir`.
pub fn write_model(
    dir: &Path,
    data: &Dataset,
    outcome: &Outcome,
    stats: &serde_json::Value,
) -> Result<(), LpcaError> {
    std::fs::create_dir_all(dir).map_err(|e| err(dir, e))?;
    let (n, d, k) = (data.n as u64, data.d as u64, outcome.models.len() as u64);
    let l = outcome.models.iter().map(|m| m.dim()).max().unwrap_or(0);
    write_npy(
        &dir.join("assignments.npy"),
        &[n],
        outcome.assignments.iter().map(|&a| a as i32),
    )?;
    write_npy(
        &dir.join("dims.npy"),
        &[k],
        outcome.models.iter().map(|m| m.dim() as i32),
    )?;
    write_npy(
        &dir.join("means.npy"),
        &[k, d],
        outcome
            .models
            .iter()
            .flat_map(|m| m.mean.iter().map(|&v| v as f32)),
    )?;
    let bases = outcome.models.iter().flat_map(|m| {
        (0..l).flat_map(move |j| {
            (0..data.d).map(move |c| m.basis.get(j).map_or(0.0, |e| e[c] as f32))
        })
    });
    write_npy(&dir.join("bases.npy"), &[k, l as u64, d], bases)?;
    let mut scratch = vec![0.0; data.d];
    let mut coeffs = Vec::with_capacity(data.n * l);
    for (i, &a) in outcome.assignments.iter().enumerate() {
        let c = outcome.models[a as usize].coefficients(data.row(i), &mut scratch);
        coeffs.extend((0..l).map(|j| c.get(j).copied().unwrap_or(0.0) as f32));
    }
    write_npy(&dir.join("coefficients.npy"), &[n, l as u64], coeffs)?;
    let text = serde_json::to_string_pretty(stats).map_err(|e| err(dir, e))?;
    let stats_path = dir.join("stats.json");
    write_text_atomically(&stats_path, &(text + "\n")).map_err(|e| err(&stats_path, e.reason))
}
