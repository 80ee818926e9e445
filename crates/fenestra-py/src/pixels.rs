//! Images as Python holds them: float32 RGB bytes, row-major, little-endian, which NumPy
//! reads as a (height, width, 3) array without a copy.

use fenestra_core::image::Image;
use fenestra_core::Rgb;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// Bytes per pixel: three float32.
const PIXEL: usize = 12;

/// `image`'s pixels as bytes.
pub fn bytes<'py>(py: Python<'py>, image: &Image) -> PyResult<Bound<'py, PyBytes>> {
    PyBytes::new_with(py, image.pixels.len() * PIXEL, |out| {
        for (chunk, p) in out.chunks_exact_mut(PIXEL).zip(&image.pixels) {
            for (c, v) in chunk.chunks_exact_mut(4).zip(p.to_array()) {
                c.copy_from_slice(&v.to_le_bytes());
            }
        }
        Ok(())
    })
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
