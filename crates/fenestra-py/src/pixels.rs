//! Images and points as Python holds them: float32 triples as little-endian bytes (images
//! row-major), which NumPy reads as a (height, width, 3) or (n, 3) array without a copy.

use fenestra_core::image::Image;
use fenestra_core::{Rgb, Vec3};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// Bytes per pixel: three float32.
const PIXEL: usize = 12;

/// Triples as bytes.
fn triples<'py>(
    py: Python<'py>,
    items: impl ExactSizeIterator<Item = [f32; 3]>,
) -> PyResult<Bound<'py, PyBytes>> {
    PyBytes::new_with(py, items.len() * PIXEL, |out| {
        for (chunk, t) in out.chunks_exact_mut(PIXEL).zip(items) {
            for (c, v) in chunk.chunks_exact_mut(4).zip(t) {
                c.copy_from_slice(&v.to_le_bytes());
            }
        }
        Ok(())
    })
}

/// `image`'s pixels as bytes.
pub fn bytes<'py>(py: Python<'py>, image: &Image) -> PyResult<Bound<'py, PyBytes>> {
    triples(py, image.pixels.iter().map(|p| p.to_array()))
}

/// Points as bytes.
pub fn points<'py>(py: Python<'py>, points: &[Vec3]) -> PyResult<Bound<'py, PyBytes>> {
    triples(py, points.iter().map(|p| p.to_array()))
}

/// The image of `width` x `height` whose pixels are `bytes`.
pub fn image(bytes: &[u8], (width, height): (usize, usize)) -> anyhow::Result<Image> {
    anyhow::ensure!(
        bytes.len() == width * height * PIXEL,
        "an image of {width}x{height} needs {} bytes of float32 RGB, got {}",
        width * height * PIXEL,
        bytes.len()
    );
    let mut out = Image::new(width, height);
    for (p, chunk) in out.pixels.iter_mut().zip(bytes.chunks_exact(PIXEL)) {
        let c = |i: usize| f32::from_le_bytes([chunk[i], chunk[i + 1], chunk[i + 2], chunk[i + 3]]);
        *p = Rgb::new(c(0), c(4), c(8));
    }
    Ok(out)
}
