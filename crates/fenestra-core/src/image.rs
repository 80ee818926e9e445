//! Linear RGB images with OpenEXR, Radiance HDR, PFM, PNG, JPEG and TGA input, EXR output
//! with metadata, and tone-mapped PNG output for looking. Files are written to a temporary name and renamed.

use crate::fs::{write_atomically, WriteError};
use crate::Rgb;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

mod pfm;

/// An image that cannot be read or written.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The file is missing or not a readable image.
    #[error("cannot read image {path}: {reason}")]
    Read {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
    /// The file could not be written.
    #[error(transparent)]
    Write(#[from] WriteError),
    /// The file name's extension names no format fenestra reads or writes.
    #[error("image {path}: unsupported extension (expected .exr, .hdr, .pfm, .png, .jpg or .tga)")]
    Extension {
        /// The file.
        path: PathBuf,
    },
}

/// An estimate of an image: the mean of each pixel's samples and the variance of that mean.
#[derive(Clone, Debug, PartialEq)]
pub struct Estimate {
    /// Per-pixel means.
    pub mean: Image,
    /// Per-pixel variances of the means.
    pub variance: Image,
}

/// A linear RGB image.
#[derive(Clone, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Row-major, top row first.
    pub pixels: Vec<Rgb>,
}

/// Its size and a fingerprint of its pixels: a texture's millions of pixels printed one by
/// one made keying a scene by its `Debug` form take seconds.
impl std::fmt::Debug for Image {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let values = self
            .pixels
            .iter()
            .flat_map(|p| [p.r, p.g, p.b].map(f32::to_bits));
        f.debug_struct("Image")
            .field("width", &self.width)
            .field("height", &self.height)
            .field(
                "pixels",
                &format_args!("{:016x}", crate::hash::fingerprint(values)),
            )
            .finish()
    }
}

impl Image {
    /// A black image.
    pub fn new(width: usize, height: usize) -> Self {
        Image {
            width,
            height,
            pixels: vec![Rgb::ZERO; width * height],
        }
    }

    /// The pixel in column `x`, row `y` (0 at the top).
    pub fn get(&self, x: usize, y: usize) -> Rgb {
        self.pixels[y * self.width + x]
    }

    /// The image `factor` times smaller on each side, each pixel the mean of a `factor` x
    /// `factor` block (a box filter): a reference rendered larger, brought to a render's size.
    /// The sides must be whole multiples of `factor`.
    pub fn downsampled(&self, factor: usize) -> Image {
        assert!(factor > 0 && self.width % factor == 0 && self.height % factor == 0);
        let mut out = Image::new(self.width / factor, self.height / factor);
        let share = 1.0 / (factor * factor) as f32;
        for y in 0..self.height {
            for x in 0..self.width {
                let (ox, oy) = (x / factor, y / factor);
                let sum = out.get(ox, oy) + self.get(x, y) * share;
                out.set(ox, oy, sum);
            }
        }
        out
    }

    /// Sets the pixel in column `x`, row `y`.
    pub fn set(&mut self, x: usize, y: usize, c: Rgb) {
        self.pixels[y * self.width + x] = c;
    }

    /// The `w` x `h` region with top-left corner (x, y), clamped to the image.
    pub fn crop(&self, x: usize, y: usize, w: usize, h: usize) -> Image {
        let (x, y) = (x.min(self.width), y.min(self.height));
        let (w, h) = (w.min(self.width - x), h.min(self.height - y));
        let mut out = Image::new(w, h);
        for j in 0..h {
            out.pixels[j * w..(j + 1) * w].copy_from_slice(
                &self.pixels[(y + j) * self.width + x..(y + j) * self.width + x + w],
            );
        }
        out
    }

    /// Each pixel repeated `k` x `k` times (nearest-neighbour zoom, for looking at noise).
    pub fn upscale(&self, k: usize) -> Image {
        let k = k.max(1);
        let mut out = Image::new(self.width * k, self.height * k);
        for y in 0..out.height {
            for x in 0..out.width {
                out.set(x, y, self.get(x / k, y / k));
            }
        }
        out
    }

    /// Mean of all pixels (f64 accumulation).
    pub fn mean(&self) -> Rgb {
        let mut acc = [0.0f64; 3];
        for p in &self.pixels {
            acc[0] += p.r as f64;
            acc[1] += p.g as f64;
            acc[2] += p.b as f64;
        }
        let n = self.pixels.len().max(1) as f64;
        Rgb::new(
            (acc[0] / n) as f32,
            (acc[1] / n) as f32,
            (acc[2] / n) as f32,
        )
    }

    /// Reads an image as linear RGB: OpenEXR, Radiance HDR and PFM as stored, PNG, JPEG and
    /// TGA decoded from sRGB.
    pub fn read(path: &Path) -> Result<Image, ImageError> {
        Self::read_encoded(path, true)
    }

    /// Reads an image of data (a normal map): every format's values as stored, 8-bit ones
    /// in [0, 1] without sRGB decoding.
    pub fn read_data(path: &Path) -> Result<Image, ImageError> {
        Self::read_encoded(path, false)
    }

    /// Reads an image, 8-bit formats decoded from sRGB if `srgb`.
    fn read_encoded(path: &Path, srgb: bool) -> Result<Image, ImageError> {
        let err = |reason: String| ImageError::Read {
            path: path.to_path_buf(),
            reason,
        };
        match extension(path).as_deref() {
            Some("exr") => {
                exr_fits(path).map_err(err)?;
                let img = exr::prelude::read_first_rgba_layer_from_file(
                    path,
                    |res, _| Image::new(res.width(), res.height()),
                    |img: &mut Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
                        img.set(pos.x(), pos.y(), Rgb::new(r, g, b))
                    },
                )
                .map_err(|e| err(e.to_string()))?;
                Ok(img.layer_data.channel_data.pixels)
            }
            Some("pfm") => {
                let bytes = std::fs::read(path).map_err(|e| err(e.to_string()))?;
                pfm::decode(&bytes).map_err(|e| err(e.to_string()))
            }
            Some("hdr" | "png" | "jpg" | "jpeg" | "tga") => {
                let open = || {
                    image::ImageReader::open(path)
                        .map_err(|e| err(e.to_string()))?
                        .with_guessed_format()
                        .map_err(|e| err(e.to_string()))
                };
                let (w, h) = open()?.into_dimensions().map_err(|e| err(e.to_string()))?;
                // The decoded image becomes RGB floats, then these pixels.
                expansion_fits(w, h, 2 * PIXEL_BYTES).map_err(err)?;
                let decoded = open()?.decode().map_err(|e| err(e.to_string()))?;
                let is_hdr = matches!(
                    decoded,
                    image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_)
                );
                let rgb = decoded.to_rgb32f();
                let (w, h) = rgb.dimensions();
                let decode = |v: f32| {
                    if is_hdr || !srgb {
                        v
                    } else {
                        srgb_to_linear(v)
                    }
                };
                let pixels = rgb
                    .pixels()
                    .map(|p| Rgb::new(decode(p[0]), decode(p[1]), decode(p[2])))
                    .collect();
                Ok(Image {
                    width: w as usize,
                    height: h as usize,
                    pixels,
                })
            }
            _ => Err(ImageError::Extension {
                path: path.to_path_buf(),
            }),
        }
    }

    /// Writes linear 32-bit float OpenEXR with the given string attributes in its header,
    /// atomically.
    pub fn write_exr(
        &self,
        path: &Path,
        metadata: &BTreeMap<String, String>,
    ) -> Result<(), ImageError> {
        Ok(write_atomically(path, |tmp| {
            self.write_exr_to(tmp, metadata)
        })?)
    }

    /// [`Image::write_exr`] straight to `path` (for a [`FileSet`](crate::fs::FileSet) that
    /// renames it into place).
    pub fn write_exr_to(
        &self,
        path: &Path,
        metadata: &BTreeMap<String, String>,
    ) -> Result<(), ImageError> {
        self.write_exr_layers_to(path, &[], metadata)
    }

    /// [`Image::write_exr_to`] with more layers in the same part, as OpenEXR names them: a
    /// layer `name` with channels `[a, b, c]` is stored as channels `name.a`, `name.b`,
    /// `name.c` (Blender's and Cycles' layout; readers of RGB see the image alone). Every
    /// layer must be the image's size.
    pub fn write_exr_layers_to(
        &self,
        path: &Path,
        layers: &[ExrLayer],
        metadata: &BTreeMap<String, String>,
    ) -> Result<(), ImageError> {
        use exr::prelude::*;
        let plain = ExrLayer {
            name: "",
            channels: ["R", "G", "B"],
            image: self,
        };
        let mut list = SmallVec::new();
        for layer in std::iter::once(&plain).chain(layers) {
            assert_eq!(
                (layer.image.width, layer.image.height),
                (self.width, self.height),
                "an EXR layer of another size"
            );
            for (c, channel) in layer.channels.iter().enumerate() {
                let name = match layer.name {
                    "" => channel.to_string(),
                    prefix => format!("{prefix}.{channel}"),
                };
                let samples = layer.image.pixels.iter().map(|p| p.to_array()[c]).collect();
                list.push(AnyChannel::new(name.as_str(), FlatSamples::F32(samples)));
            }
        }
        let layer = Layer::new(
            (self.width, self.height),
            LayerAttributes::named("rgb"),
            // RLE in 64x64 tiles, as FAST_LOSSLESS, but in increasing order: tiles compressed
            // in parallel are then written sorted, so that the same image makes the same file
            // (in unspecified order they land as threads finish them).
            Encoding {
                line_order: LineOrder::Increasing,
                ..Encoding::FAST_LOSSLESS
            },
            AnyChannels::sort(list),
        );
        let mut image = exr::image::Image::from_layer(layer);
        for (k, v) in metadata {
            let (Some(k), Some(v)) = (Text::new_or_none(latin1(k)), Text::new_or_none(latin1(v)))
            else {
                continue;
            };
            image.attributes.other.insert(k, AttributeValue::Text(v));
        }
        image
            .write()
            .to_file(path)
            .map_err(|e| WriteError::new(path, e).into())
    }

    /// Writes an 8-bit sRGB PNG after scaling by 2^stops, atomically; `None` picks the
    /// exposure that maps the log-average luminance to middle grey (Reinhard's key value
    /// 0.18).
    pub fn write_png(&self, path: &Path, exposure_stops: Option<f32>) -> Result<(), ImageError> {
        Ok(write_atomically(path, |tmp| {
            self.write_png_to(tmp, exposure_stops)
        })?)
    }

    /// [`Image::write_png`] straight to `path`.
    pub fn write_png_to(&self, path: &Path, exposure_stops: Option<f32>) -> Result<(), ImageError> {
        let bytes = self
            .png(exposure_stops)
            .map_err(|e| WriteError::new(path, e))?;
        std::fs::write(path, bytes).map_err(|e| WriteError::new(path, e).into())
    }

    /// The 8-bit sRGB PNG [`Image::write_png`] writes, as bytes.
    pub fn png(&self, exposure_stops: Option<f32>) -> Result<Vec<u8>, image::ImageError> {
        let scale = match exposure_stops {
            Some(ev) => 2f32.powf(ev),
            None => self.auto_exposure_scale(),
        };
        if let Some(ev) = exposure_stops.filter(|_| !(scale.is_finite() && scale > 0.0)) {
            let why = format!(
                "exposure must be a finite number of stops within 32-bit floats' range, got {ev}"
            );
            return Err(image::ImageError::Parameter(
                image::error::ParameterError::from_kind(image::error::ParameterErrorKind::Generic(
                    why,
                )),
            ));
        }
        let mut bytes = Vec::with_capacity(self.pixels.len() * 3);
        for p in &self.pixels {
            for v in p.to_array() {
                let v = if v.is_finite() { v * scale } else { 0.0 };
                bytes.push((linear_to_srgb(v.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8);
            }
        }
        let mut out = std::io::Cursor::new(Vec::new());
        image::write_buffer_with_format(
            &mut out,
            &bytes,
            self.width as u32,
            self.height as u32,
            image::ExtendedColorType::Rgb8,
            image::ImageFormat::Png,
        )?;
        Ok(out.into_inner())
    }

    /// The scale that maps the log-average luminance to middle grey (0.18).
    pub fn auto_exposure_scale(&self) -> f32 {
        let (mut sum, mut n) = (0.0f64, 0usize);
        for p in &self.pixels {
            let l = p.luminance();
            if l.is_finite() && l > 0.0 {
                sum += (l as f64 + 1e-6).ln();
                n += 1;
            }
        }
        if n == 0 {
            return 1.0;
        }
        let log_avg = (sum / n as f64).exp() as f32;
        0.18 / log_avg
    }
}

/// A layer of an OpenEXR file beside its RGB image ([`Image::write_exr_layers_to`]).
#[derive(Clone, Copy, Debug)]
pub struct ExrLayer<'a> {
    /// The layer's name: its channels' prefix.
    pub name: &'a str,
    /// Its three channels' names ("R", "G", "B"; "X", "Y", "Z").
    pub channels: [&'a str; 3],
    /// Its pixels.
    pub image: &'a Image,
}

/// Bytes of one pixel of an [`Image`].
pub const PIXEL_BYTES: u64 = std::mem::size_of::<Rgb>() as u64;

/// Whether the process can get `bytes_per_pixel` for each pixel of a `w` x `h` image
/// decoded from a file (a compressed file may declare far more than it holds: a
/// decompression bomb); the reason if not.
pub fn expansion_fits(w: u32, h: u32, bytes_per_pixel: u64) -> Result<(), String> {
    let needed = u64::from(w) * u64::from(h) * bytes_per_pixel;
    crate::memory::ensure(needed, || format!("decoding its {w}x{h} pixels"))
        .map_err(|e| e.to_string())
}

/// Whether the OpenEXR file at `path` can hold the image its header declares and the process
/// can hold it decoded: its chunk offset tables alone (8 bytes a chunk) must fit in the file,
/// and its pixels in memory. The reason if not.
fn exr_fits(path: &Path) -> Result<(), String> {
    let size = std::fs::metadata(path).map_err(|e| e.to_string())?.len();
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| e.to_string())?;
    let offsets: u64 = meta.headers.iter().map(|h| 8 * h.chunk_count as u64).sum();
    let Some(first) = meta.headers.first() else {
        return Err("it has no image part".into());
    };
    let (w, h) = (first.layer_size.width(), first.layer_size.height());
    if offsets > size {
        return Err(format!(
            "its header declares a {w}x{h} image in {} chunks, whose offset table alone ({offsets} bytes) is larger than the file ({size} bytes): truncated or forged",
            meta.headers.iter().map(|h| h.chunk_count).sum::<usize>()
        ));
    }
    expansion_fits(w as u32, h as u32, PIXEL_BYTES)
}

/// String attributes from an OpenEXR file's header.
pub fn read_exr_metadata(path: &Path) -> Result<BTreeMap<String, String>, ImageError> {
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| ImageError::Read {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    let mut out = BTreeMap::new();
    let shared = meta.headers.iter().flat_map(|h| {
        h.shared_attributes
            .other
            .iter()
            .chain(h.own_attributes.other.iter())
    });
    for (k, v) in shared {
        if let exr::meta::attribute::AttributeValue::Text(t) = v {
            out.insert(k.to_string(), t.to_string());
        }
    }
    Ok(out)
}

/// A layer of the OpenEXR file at `path`: the channels `name.c` for `c` in `channels` of its
/// first part ([`Image::write_exr_layers_to`]'s layout).
pub fn read_exr_layer(path: &Path, name: &str, channels: [&str; 3]) -> Result<Image, ImageError> {
    let err = |reason: String| ImageError::Read {
        path: path.to_path_buf(),
        reason,
    };
    exr_fits(path).map_err(err)?;
    // Every channel of every part is decoded, 4 bytes each a pixel: more than exr_fits asks
    // of an RGB image.
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| err(e.to_string()))?;
    let needed: u64 = (meta.headers.iter())
        .map(|p| p.layer_size.area() as u64 * 4 * p.channels.list.len() as u64)
        .sum();
    crate::memory::ensure(needed, || "decoding its channels".into())
        .map_err(|e| err(e.to_string()))?;
    let file =
        exr::prelude::read_all_flat_layers_from_file(path).map_err(|e| err(e.to_string()))?;
    let Some(part) = file.layer_data.first() else {
        return Err(err("it has no image part".into()));
    };
    let (w, h) = (part.size.width(), part.size.height());
    let mut values = Vec::with_capacity(3);
    for c in channels {
        let full = format!("{name}.{c}");
        let channel = (part.channel_data.list.iter())
            .find(|ch| ch.name.to_string() == full)
            .ok_or_else(|| err(format!("it has no channel {full}")))?;
        values.push(channel.sample_data.values_as_f32().collect::<Vec<f32>>());
    }
    let mut image = Image::new(w, h);
    for (i, p) in image.pixels.iter_mut().enumerate() {
        *p = Rgb::new(values[0][i], values[1][i], values[2][i]);
    }
    Ok(image)
}

/// The channel names of an OpenEXR file's first part, in the file's order (OpenEXR sorts
/// them: "A", "B", "G", "R").
pub fn read_exr_channel_names(path: &Path) -> Result<Vec<String>, ImageError> {
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| ImageError::Read {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    Ok(meta
        .headers
        .first()
        .map(|h| h.channels.list.iter().map(|c| c.name.to_string()).collect())
        .unwrap_or_default())
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
}

fn latin1(s: &str) -> String {
    s.chars()
        .map(|c| if (c as u32) < 256 { c } else { '?' })
        .collect()
}

/// The sRGB transfer function inverted: an encoded value in [0, 1] to linear.
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// The sRGB transfer function: a linear value in [0, 1] to its encoding.
pub fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downsampling_averages_blocks() {
        let mut img = Image::new(4, 2);
        for (i, p) in img.pixels.iter_mut().enumerate() {
            *p = Rgb::splat(i as f32);
        }
        let small = img.downsampled(2);
        assert_eq!((small.width, small.height), (2, 1));
        // Blocks (0, 1, 4, 5) and (2, 3, 6, 7).
        assert_eq!(small.pixels, vec![Rgb::splat(2.5), Rgb::splat(4.5)]);
        assert_eq!(img.downsampled(1).pixels, img.pixels);
    }

    fn tmpdir() -> PathBuf {
        let d = std::env::temp_dir().join(format!("fenestra-image-test-{}", std::process::id()));
        std::fs::create_dir_all(&d).expect("temp dir");
        d
    }

    #[test]
    fn exr_round_trip_keeps_pixels_and_metadata() {
        let mut img = Image::new(3, 2);
        img.set(2, 1, Rgb::new(1.5, -0.25, 1e4));
        img.set(0, 0, Rgb::new(0.1, 0.2, 0.3));
        let path = tmpdir().join("rt.exr");
        let meta = BTreeMap::from([("fenestra:spp".to_string(), "64".to_string())]);
        img.write_exr(&path, &meta).expect("write");
        assert_eq!(Image::read(&path).expect("read"), img);
        assert_eq!(
            read_exr_metadata(&path)
                .expect("meta")
                .get("fenestra:spp")
                .map(String::as_str),
            Some("64")
        );
    }

    #[test]
    fn the_same_image_makes_the_same_exr_file() {
        // Many tiles of varied content, compressed in parallel.
        let (w, h) = (700, 400);
        let mut img = Image::new(w, h);
        for y in 0..h {
            for x in 0..w {
                let v = ((x * 7 + y * 13) % 97) as f32
                    * if (x / 64 + y / 64) % 2 == 0 {
                        1.0
                    } else {
                        0.01
                    };
                img.set(x, y, Rgb::new(v, v * 0.5, (x % 5) as f32));
            }
        }
        let meta = BTreeMap::new();
        let files: Vec<Vec<u8>> = (0..6)
            .map(|k| {
                let path = tmpdir().join(format!("same-{k}.exr"));
                img.write_exr(&path, &meta).expect("write");
                std::fs::read(&path).expect("read")
            })
            .collect();
        assert!(files.iter().all(|f| *f == files[0]), "the files differ");
    }

    #[test]
    fn png_is_written_and_srgb_round_trips() {
        let mut img = Image::new(2, 2);
        img.set(1, 1, Rgb::splat(0.5));
        let path = tmpdir().join("t.png");
        img.write_png(&path, Some(0.0)).expect("png");
        let back = Image::read(&path).expect("read png");
        assert!((back.get(1, 1).r - 0.5).abs() < 0.01);
        for v in [0.0, 0.002, 0.2, 0.9, 1.0] {
            assert!((srgb_to_linear(linear_to_srgb(v)) - v).abs() < 1e-5);
        }
    }

    #[test]
    fn tga_jpeg_and_pfm_are_read_as_linear_rgb() {
        // 8-bit formats hold sRGB: 188 is linear 0.5.
        let srgb = image::RgbImage::from_fn(2, 1, |x, _| image::Rgb([188, 188 * x as u8, 0]));
        for (name, format, tolerance) in [
            ("t.tga", image::ImageFormat::Tga, 0.0),
            ("t.jpg", image::ImageFormat::Jpeg, 0.05),
        ] {
            let path = tmpdir().join(name);
            srgb.save_with_format(&path, format).expect("save");
            let img = Image::read(&path).expect(name);
            assert_eq!((img.width, img.height), (2, 1), "{name}");
            assert!((img.get(0, 0).r - srgb_to_linear(188.0 / 255.0)).abs() <= tolerance);
            assert!((img.get(1, 0).g - 0.5).abs() < 0.01 + tolerance, "{name}");
        }
        let path = tmpdir().join("t.pfm");
        let mut pfm = b"PF\n1 1\n-1\n".to_vec();
        pfm.extend([2.0f32, 0.5, 0.0].iter().flat_map(|f| f.to_le_bytes()));
        std::fs::write(&path, pfm).expect("pfm");
        assert_eq!(
            Image::read(&path).expect("pfm").pixels,
            [Rgb::new(2.0, 0.5, 0.0)]
        );
    }

    #[test]
    fn reading_a_missing_or_unknown_file_is_an_error() {
        assert!(matches!(
            Image::read(Path::new("/nonexistent/x.exr")),
            Err(ImageError::Read { .. })
        ));
        assert!(matches!(
            Image::read(Path::new("x.tiff")),
            Err(ImageError::Extension { .. })
        ));
    }
}
