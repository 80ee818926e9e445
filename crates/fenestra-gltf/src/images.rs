//! The images textures use, read and decoded in parallel: colour as sRGB, data (roughness,
//! metalness, normals) as stored.

use crate::error::GltfError;
use crate::source::Source;
use fenestra_core::image::{expansion_fits, srgb_to_linear, Image, PIXEL_BYTES};
use fenestra_core::Rgb;
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// How an image's texel values are meant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Encoding {
    /// Colour: sRGB-encoded 8-bit values, decoded to linear.
    Srgb,
    /// Data: values as stored, scaled to [0, 1].
    Linear,
    /// The alpha channel (1 where the image has none), in every channel.
    Alpha,
}

/// Decoded images by glTF image index and encoding, with where each came from.
#[derive(Default)]
pub struct Images {
    decoded: HashMap<(usize, Encoding), (Arc<Image>, PathBuf)>,
}

impl Images {
    /// Reads and decodes every (image, encoding) in `wanted`.
    pub fn decode(src: &mut Source, wanted: &[(usize, Encoding)]) -> Result<Images, GltfError> {
        let mut bytes: HashMap<usize, (Vec<u8>, PathBuf)> = HashMap::new();
        for &(i, _) in wanted {
            if bytes.contains_key(&i) {
                continue;
            }
            let at = format!("/images/{i}");
            // Read from the JSON: the gltf crate's `Image::source` unwraps a missing
            // mimeType or uri (found by fuzzing).
            let image = src
                .document
                .as_json()
                .images
                .get(i)
                .ok_or_else(|| GltfError::at(&src.path, &at, "no such image"))?;
            let uri = match (&image.buffer_view, &image.uri) {
                (Some(view), _) => {
                    let view = src.document.views().nth(view.value()).ok_or_else(|| {
                        GltfError::at(&src.path, &at, "its bufferView is out of range")
                    })?;
                    let buffer = &src.buffers[view.buffer().index()];
                    let range = view.offset()..view.offset().saturating_add(view.length());
                    let data = buffer.get(range).ok_or_else(|| {
                        GltfError::at(&src.path, &at, "its buffer view lies beyond its buffer")
                    })?;
                    let name = src.path.with_extension(format!("image{i}"));
                    bytes.insert(i, (data.to_vec(), name));
                    continue;
                }
                (None, Some(uri)) => uri.clone(),
                (None, None) => {
                    return Err(GltfError::at(
                        &src.path,
                        &at,
                        "has neither a uri nor a bufferView",
                    ))
                }
            };
            let read = (src.read_uri(&uri, &at)?, src.file_of(&uri));
            bytes.insert(i, read);
        }
        // Each image decoded once, then converted to every encoding asked of it (a MASK
        // material's base colour is read as colour and as alpha).
        let path = src.path.clone();
        let mut images: Vec<(usize, Vec<Encoding>)> = Vec::new();
        for &(i, encoding) in wanted {
            match images.iter_mut().find(|(j, _)| *j == i) {
                Some((_, encodings)) => encodings.push(encoding),
                None => images.push((i, vec![encoding])),
            }
        }
        let decoded = images
            .par_iter()
            .map(|(i, encodings)| {
                let (data, file) = &bytes[i];
                let err = |e: String| {
                    GltfError::at(
                        &path,
                        format!("/images/{i}"),
                        format!("{}: {e}", file.display()),
                    )
                };
                let reader = || {
                    image::ImageReader::new(std::io::Cursor::new(data))
                        .with_guessed_format()
                        .map_err(|e| err(e.to_string()))
                };
                let (w, h) = reader()?
                    .into_dimensions()
                    .map_err(|e| err(e.to_string()))?;
                // Each encoding's pixels, and the conversion's buffer (RGBA floats at most).
                let per_pixel = encodings.len() as u64 * PIXEL_BYTES + 16;
                expansion_fits(w, h, per_pixel).map_err(err)?;
                let image = reader()?.decode().map_err(|e| err(e.to_string()))?;
                Ok(encodings
                    .iter()
                    .map(|&e| ((*i, e), (Arc::new(convert(&image, e)), file.clone())))
                    .collect::<Vec<_>>())
            })
            .collect::<Result<Vec<_>, GltfError>>()?
            .into_iter()
            .flatten()
            .collect();
        Ok(Images { decoded })
    }

    /// Image `i` decoded as `encoding` (it must have been asked for), with its file.
    pub fn get(&self, i: usize, encoding: Encoding) -> Option<&(Arc<Image>, PathBuf)> {
        self.decoded.get(&(i, encoding))
    }
}

/// A decoded PNG or JPEG (or any format the `image` crate knows) as linear RGB; 8-bit
/// images through a table (sRGB decoding per texel is most of a large scene's load time).
fn convert(decoded: &image::DynamicImage, encoding: Encoding) -> Image {
    let (w, h) = (decoded.width() as usize, decoded.height() as usize);
    let pixels = if encoding == Encoding::Alpha {
        decoded
            .to_rgba32f()
            .pixels()
            .map(|p| Rgb::splat(p[3]))
            .collect()
    } else if decoded.color().bytes_per_pixel() / decoded.color().channel_count() == 1 {
        let table: Vec<f32> = (0..256)
            .map(|v| match encoding {
                Encoding::Srgb => srgb_to_linear(v as f32 / 255.0),
                _ => v as f32 / 255.0,
            })
            .collect();
        let t = |v: u8| table[v as usize];
        decoded
            .to_rgb8()
            .pixels()
            .map(|p| Rgb::new(t(p[0]), t(p[1]), t(p[2])))
            .collect()
    } else {
        let f = match encoding {
            Encoding::Srgb => srgb_to_linear,
            _ => |v: f32| v,
        };
        decoded
            .to_rgb32f()
            .pixels()
            .map(|p| Rgb::new(f(p[0]), f(p[1]), f(p[2])))
            .collect()
    };
    Image {
        width: w,
        height: h,
        pixels,
    }
}
