//! The measurement toolkit on images given as float32 bytes (NumPy arrays): metrics against
//! a reference, the z-test of agreement, images read from files, tone-mapped PNGs.

use crate::error;
use crate::pixels::{bytes, image};
use fenestra_core::image::{read_exr_channel_names, read_exr_layer, Estimate, Image, ImageError};
use fenestra_eval::{metrics, ztest};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use serde_json::json;

/// Metrics of `img` against `reference` as JSON (MSE, relative MSE, MAE, means, 8x8 region
/// error, worst region's share; the efficiency if `img` took `time` seconds); with both images' variances of the mean, also the z-test of
/// agreement (whole image and `region`-pixel blocks at significance `alpha`) and the shift
/// of the image mean with its standard error.
#[pyfunction]
#[pyo3(signature = (img, reference, size, time=None, img_variance=None,
    reference_variance=None, alpha=0.01, region=16))]
#[allow(clippy::too_many_arguments)]
pub fn compare(
    img: &[u8],
    reference: &[u8],
    size: (usize, usize),
    time: Option<f64>,
    img_variance: Option<&[u8]>,
    reference_variance: Option<&[u8]>,
    alpha: f64,
    region: usize,
) -> PyResult<String> {
    let run = || -> anyhow::Result<String> {
        let (a, r) = (image(img, size)?, image(reference, size)?);
        let m = metrics::compare(&a, &r)?;
        let efficiency = time.map(|t| metrics::efficiency(m.mse, t));
        let mut out = json!({ "metrics": m, "efficiency": efficiency });
        if let (Some(va), Some(vr)) = (img_variance, reference_variance) {
            let a = Estimate {
                mean: a,
                variance: image(va, size)?,
            };
            let r = Estimate {
                mean: r,
                variance: image(vr, size)?,
            };
            out["agreement"] = json!(ztest::agreement(&r, &a, alpha, region)?);
            let shift = ztest::mean_shift(&r, &a)?;
            out["mean_shift"] = json!({
                "relative": shift.relative,
                "standard_error": shift.standard_error,
                "z": shift.z(),
            });
        }
        Ok(out.to_string())
    };
    run().map_err(error)
}

/// An image file (EXR, HDR, PFM, PNG) as (float32 RGB bytes, width, height).
#[pyfunction]
pub fn read_image<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
) -> PyResult<(Bound<'py, PyBytes>, usize, usize)> {
    let img = Image::read(&path).map_err(|e| error(anyhow::anyhow!("{}: {e}", path.display())))?;
    Ok((bytes(py, &img)?, img.width, img.height))
}

/// The denoising features an EXR holds as its layers `albedo` and `normal` (what
/// `fenestra render --features` writes), as (albedo, normal) float32 RGB bytes; `None` if it
/// holds none (or is not an EXR).
#[pyfunction]
pub fn read_features<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
) -> PyResult<Option<(Bound<'py, PyBytes>, Bound<'py, PyBytes>)>> {
    let is_exr = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    let failed = |e: ImageError| error(anyhow::anyhow!("{}: {e}", path.display()));
    if !is_exr
        || !read_exr_channel_names(&path)
            .map_err(failed)?
            .iter()
            .any(|c| c == "albedo.R")
    {
        return Ok(None);
    }
    let albedo = read_exr_layer(&path, "albedo", ["R", "G", "B"]).map_err(failed)?;
    let normal = read_exr_layer(&path, "normal", ["X", "Y", "Z"]).map_err(failed)?;
    Ok(Some((bytes(py, &albedo)?, bytes(py, &normal)?)))
}

/// The PNG the command line writes for an image: sRGB, tone-mapped at `exposure` stops
/// (automatic: log-average luminance to middle grey).
#[pyfunction]
#[pyo3(signature = (pixels, size, exposure=None))]
pub fn png<'py>(
    py: Python<'py>,
    pixels: &[u8],
    size: (usize, usize),
    exposure: Option<f32>,
) -> PyResult<Bound<'py, PyBytes>> {
    let img = image(pixels, size).map_err(error)?;
    let png = img.png(exposure).map_err(|e| error(e.into()))?;
    Ok(PyBytes::new(py, &png))
}
