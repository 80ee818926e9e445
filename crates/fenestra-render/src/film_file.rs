//! The film-state file (`.film`): a render's exact accumulators, so that pieces of one render
//! made on different machines (sample ranges, tiles) merge into the image one machine would
//! have made, bit for bit. docs/scale-out.md documents the format:
//!
//! ```text
//! magic    "FENESTRA-FILM\n"                       14 bytes
//! version  u32 little-endian (2)
//! length   u32 little-endian: bytes of the header
//! header   JSON (FilmHeader): what was rendered, the window, the sample range, statistics
//! paths    u64 little-endian: light paths traced into the film (0: none, and no splats)
//! pixels   per pixel of the window, row-major, 100 bytes each, little-endian:
//!          count u32, sums 3 x i128, sums of squares 3 x u128 (units of 2^-64)
//! splats   if paths > 0: per pixel, as pixels, the sums of the light paths' splats there
//! features if the header says `features`: per pixel, 28 bytes, little-endian: count u32,
//!          albedo sums 3 x i32, normal sums 3 x i32 (units of 2^-24)
//! crc      u32 little-endian: CRC-32 of every byte before it
//! ```
//!
//! Version 1 had no `paths` and no splats; it is read as a film without light paths.
//! Version 2 had no features.

use crate::features::{FeaturePixel, FEATURE_SAMPLES};
use crate::film::{Film, Pixel, Window, ONE};
use fenestra_core::stats::RenderStats;
use serde::{Deserialize, Serialize};
use std::io::{BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 14] = b"FENESTRA-FILM\n";
const VERSION: u32 = 3;
/// Bytes of one pixel's record.
const PIXEL_BYTES: usize = 4 + 3 * 16 + 3 * 16;
/// Bytes of one pixel's feature record.
const FEATURE_BYTES: usize = 4 + 3 * 4 + 3 * 4;
/// Largest header accepted (a corrupt length must not allocate gigabytes).
const MAX_HEADER: u32 = 16 << 20;

/// Sample indices `start..end` of every pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SampleRange {
    /// First sample index.
    pub start: u32,
    /// One past the last.
    pub end: u32,
}

impl std::fmt::Display for SampleRange {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "{}..{}", self.start, self.end)
    }
}

/// What a film-state file holds besides its pixels.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FilmHeader {
    /// Hash of everything that changes the picture but the samples and the window (scene
    /// content, integrator and its settings, seed, resolution, ray backend, version): parts
    /// merge only when theirs are equal.
    pub key: String,
    /// The sample indices every pixel took; none for integrators that decide their own
    /// samples (adaptive ones split by tiles only).
    pub samples: Option<SampleRange>,
    /// The part of the image it holds.
    pub window: Window,
    /// The render's statistics (scene, integrator, settings, rays, time).
    pub stats: RenderStats,
    /// Whether the film holds denoising features ([`write`] sets it from the film).
    #[serde(default)]
    pub features: bool,
}

/// Why a film-state file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum FilmFileError {
    /// Reading failed.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Not a film-state file, a newer version, or damaged.
    #[error("{path} is not a usable film-state file: {reason}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
}

/// Writes `film` with `header` to `path` (the caller makes it atomic: [`crate::output`]
/// stages it with the render's other files).
pub fn write(path: &Path, header: &FilmHeader, film: &Film) -> std::io::Result<()> {
    let mut out = Crc(
        BufWriter::new(std::fs::File::create(path)?),
        crc32fast::Hasher::new(),
    );
    let header = FilmHeader {
        features: film.takes_features(),
        ..header.clone()
    };
    let json = serde_json::to_vec(&header)?;
    out.write_all(MAGIC)?;
    out.write_all(&VERSION.to_le_bytes())?;
    out.write_all(&(json.len() as u32).to_le_bytes())?;
    out.write_all(&json)?;
    out.write_all(&film.light_paths.to_le_bytes())?;
    for p in &film.pixels {
        out.write_all(&encode(p))?;
    }
    if film.light_paths > 0 {
        let none = Pixel::default();
        for i in 0..film.pixels.len() {
            out.write_all(&encode(film.splats.get(i).unwrap_or(&none)))?;
        }
    }
    for f in &film.features {
        out.write_all(&encode_feature(f))?;
    }
    let crc = out.1.clone().finalize();
    out.0.write_all(&crc.to_le_bytes())?;
    out.0.into_inner().map_err(|e| e.into_error())?.sync_all()
}

/// Reads only the header of the film-state file at `path` (to check parts before merging).
pub fn read_header(path: &Path) -> Result<FilmHeader, FilmFileError> {
    Ok(FilmReader::open(path)?.header)
}

/// Reads the film-state file at `path`: its header and its film, checked whole.
pub fn read(path: &Path) -> Result<(FilmHeader, Film), FilmFileError> {
    let mut reader = FilmReader::open(path)?;
    let mut film = Film::cropped(reader.header.window);
    if reader.header.features {
        film = film.with_features();
    }
    film.light_paths = reader.light_paths;
    if reader.light_paths > 0 {
        film.splats = vec![Pixel::default(); film.pixels.len()];
    }
    let mut features = std::mem::take(&mut film.features);
    reader.records(
        |record, i, p| match record {
            Record::Pixel => film.pixels[i] = p,
            Record::Splat => film.splats[i] = p,
        },
        |i, f| features[i] = f,
    )?;
    film.features = features;
    Ok((reader.header, film))
}

/// Reads the film-state file at `path` through without keeping it: whether it is whole (its
/// checksum) and every pixel record possible (see [`read`]).
pub fn verify(path: &Path) -> Result<FilmHeader, FilmFileError> {
    let mut reader = FilmReader::open(path)?;
    reader.records(|_, _, _| (), |_, _| ())?;
    Ok(reader.header)
}

/// Adds the pixels of the film-state file at `path` into `film`, whose window contains the
/// file's: merging without holding the part in memory. The file is checked whole: on an
/// error `film` holds a partial sum and must be dropped.
pub fn add_into(path: &Path, film: &mut Film) -> Result<FilmHeader, FilmFileError> {
    let mut reader = FilmReader::open(path)?;
    let (inner, outer) = (reader.header.window, film.window);
    if !(inner.full_width == outer.full_width
        && inner.full_height == outer.full_height
        && outer.x0 <= inner.x0
        && outer.y0 <= inner.y0
        && inner.x1 <= outer.x1
        && inner.y1 <= outer.y1)
    {
        return Err(reader.invalid(format!("its window {inner} is outside {outer}")));
    }
    if reader.header.features != film.takes_features() {
        let (has, lacks) = match reader.header.features {
            true => ("it holds", "the film it is added to does not"),
            false => ("it lacks", "the film it is added to holds them"),
        };
        return Err(reader.invalid(format!("{has} denoising features, {lacks}")));
    }
    let w = inner.width() as usize;
    let Some(light_paths) = film.light_paths.checked_add(reader.light_paths) else {
        return Err(reader.invalid(
            "it holds more light paths than can be counted with the other parts'".into(),
        ));
    };
    film.light_paths = light_paths;
    if reader.light_paths > 0 && film.splats.is_empty() {
        film.splats = vec![Pixel::default(); film.pixels.len()];
    }
    let mut overflow = None;
    let at = |i: usize| {
        let (x, y) = (inner.x0 as usize + i % w, inner.y0 as usize + i / w);
        (
            (y - outer.y0 as usize) * outer.width() as usize + (x - outer.x0 as usize),
            (x, y),
        )
    };
    let mut features = std::mem::take(&mut film.features);
    let mut feature_overflow = None;
    reader.records(
        |record, i, p| {
            let (at, xy) = at(i);
            let sums = match record {
                Record::Pixel => &mut film.pixels[at],
                Record::Splat => &mut film.splats[at],
            };
            if !sums.checked_merge(&p) {
                overflow.get_or_insert(xy);
            }
        },
        |i, f| {
            let (at, xy) = at(i);
            if !features[at].checked_merge(&f) || features[at].count > FEATURE_SAMPLES {
                feature_overflow.get_or_insert(xy);
            }
        },
    )?;
    film.features = features;
    let overflow = overflow.or(feature_overflow);
    if let Some((x, y)) = overflow {
        return Err(reader.invalid(format!(
            "pixel ({x}, {y}) holds more than its accumulators can take together with the \
             other parts'"
        )));
    }
    Ok(reader.header)
}

struct FilmReader {
    path: PathBuf,
    input: Crc<BufReader<std::fs::File>>,
    header: FilmHeader,
    /// Light paths traced into the film (0: the file holds no splats).
    light_paths: u64,
}

/// Which of a pixel's two records: the camera samples' sums or the light paths' splats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Record {
    Pixel,
    Splat,
}

impl FilmReader {
    fn open(path: &Path) -> Result<FilmReader, FilmFileError> {
        let io = |source| FilmFileError::Io {
            path: path.to_path_buf(),
            source,
        };
        let file = std::fs::File::open(path).map_err(io)?;
        let size = file.metadata().map_err(io)?.len();
        let mut input = Crc(BufReader::new(file), crc32fast::Hasher::new());
        let invalid = |reason: String| FilmFileError::Invalid {
            path: path.to_path_buf(),
            reason,
        };
        let mut magic = [0u8; 14];
        let mut word = [0u8; 4];
        if input.read_exact(&mut magic).is_err() || &magic != MAGIC {
            return Err(invalid("it does not start with FENESTRA-FILM".into()));
        }
        input.read_exact(&mut word).map_err(io)?;
        let version = u32::from_le_bytes(word);
        if !(1..=VERSION).contains(&version) {
            return Err(invalid(format!(
                "format version {version}, this fenestra reads versions 1 to {VERSION}"
            )));
        }
        // Bytes besides the header and the records: magic, version, length, CRC, and from
        // version 2 the light-path count.
        let framing = 26 + if version >= 2 { 8 } else { 0 };
        input.read_exact(&mut word).map_err(io)?;
        let length = u32::from_le_bytes(word);
        if length > MAX_HEADER || u64::from(length) + framing > size {
            return Err(invalid(format!(
                "truncated or corrupt: a header of {length} bytes in a file of {size}"
            )));
        }
        let mut json = vec![0u8; length as usize];
        input.read_exact(&mut json).map_err(io)?;
        let header: FilmHeader = serde_json::from_slice(&json)
            .map_err(|e| invalid(format!("its header does not parse: {e}")))?;
        let mut light_paths = 0;
        if version >= 2 {
            let mut count = [0u8; 8];
            input.read_exact(&mut count).map_err(io)?;
            light_paths = u64::from_le_bytes(count);
        }
        let w = header.window;
        if w.x0 >= w.x1 || w.y0 >= w.y1 || w.x1 > w.full_width || w.y1 > w.full_height {
            return Err(invalid(format!(
                "its window {w} does not fit a {}x{} image",
                w.full_width, w.full_height
            )));
        }
        if let Some(r) = header.samples.filter(|r| r.start >= r.end) {
            return Err(invalid(format!("its sample range {r} is empty")));
        }
        if (header.stats.width, header.stats.height) != (w.width(), w.height()) {
            return Err(invalid(format!(
                "its statistics are of a {}x{} film, its window {w} is {}x{}",
                header.stats.width,
                header.stats.height,
                w.width(),
                w.height()
            )));
        }
        let records = if light_paths > 0 { 2 } else { 1 };
        let features = if header.features { FEATURE_BYTES } else { 0 };
        let expected = framing
            + u64::from(length)
            + u64::from(w.width())
                * u64::from(w.height())
                * (records * PIXEL_BYTES as u64 + features as u64);
        if size != expected {
            return Err(invalid(format!(
                "truncated or corrupt: {size} bytes where its header promises {expected}"
            )));
        }
        Ok(FilmReader {
            path: path.to_path_buf(),
            input,
            header,
            light_paths,
        })
    }

    fn invalid(&self, reason: String) -> FilmFileError {
        FilmFileError::Invalid {
            path: self.path.clone(),
            reason,
        }
    }

    /// Hands every record, in order (the pixels', then the splats', to `each`; the features'
    /// to `each_feature`) with its pixel's index in the window, then checks the CRC.
    fn records(
        &mut self,
        mut each: impl FnMut(Record, usize, Pixel),
        mut each_feature: impl FnMut(usize, FeaturePixel),
    ) -> Result<(), FilmFileError> {
        let path = self.path.clone();
        let io = |source| FilmFileError::Io {
            path: path.clone(),
            source,
        };
        let w = self.header.window;
        // Every pixel of a sample range took at most its samples (fewer where some were
        // dropped as non-finite); an adaptive render's at most its largest count.
        let most = (self.header.samples).map_or(self.header.stats.spp_max, |r| r.end - r.start);
        let mut impossible = None;
        // Samples a sample range's pixels lack: only those dropped as non-finite.
        let mut missing = 0u64;
        let mut bytes = [0u8; PIXEL_BYTES];
        let kinds: &[Record] = if self.light_paths > 0 {
            &[Record::Pixel, Record::Splat]
        } else {
            &[Record::Pixel]
        };
        for &record in kinds {
            // A pixel's splats are as many as its light paths' vertices that land in it:
            // no bound on their number, only on their sums.
            let most = if record == Record::Pixel {
                most
            } else {
                u32::MAX
            };
            for i in 0..w.width() as usize * w.height() as usize {
                self.input.read_exact(&mut bytes).map_err(io)?;
                let pixel = decode(&bytes);
                if let (None, Some(why)) = (&impossible, impossible_pixel(&pixel, most)) {
                    let (x, y) = (
                        w.x0 as usize + i % w.width() as usize,
                        w.y0 as usize + i / w.width() as usize,
                    );
                    let what = if record == Record::Pixel {
                        ""
                    } else {
                        "'s splats"
                    };
                    impossible = Some(format!("pixel ({x}, {y}){what} {why}"));
                }
                if record == Record::Pixel && self.header.samples.is_some() {
                    missing += u64::from(most.saturating_sub(pixel.count));
                }
                each(record, i, pixel);
            }
        }
        let mut bytes = [0u8; FEATURE_BYTES];
        let pixels = w.width() as usize * w.height() as usize;
        for i in (0..pixels).filter(|_| self.header.features) {
            self.input.read_exact(&mut bytes).map_err(io)?;
            let f = decode_feature(&bytes);
            let why = match f.count > FEATURE_SAMPLES {
                true => Some(format!(
                    "holds {} feature samples, at most {FEATURE_SAMPLES}",
                    f.count
                )),
                false => f.impossible(),
            };
            if let (None, Some(why)) = (&impossible, why) {
                let (x, y) = (
                    w.x0 as usize + i % w.width() as usize,
                    w.y0 as usize + i / w.width() as usize,
                );
                impossible = Some(format!("pixel ({x}, {y}) {why}"));
            }
            each_feature(i, f);
        }
        let crc = self.input.1.clone().finalize();
        let mut word = [0u8; 4];
        self.input.0.read_exact(&mut word).map_err(io)?;
        if u32::from_le_bytes(word) != crc {
            return Err(self.invalid(
                "damaged: its checksum does not match its content (header or pixels)".into(),
            ));
        }
        let dropped = self.header.stats.rays.dropped;
        if impossible.is_none() && missing > dropped {
            impossible = Some(format!(
                "its pixels lack {missing} of their samples, and it dropped {dropped}"
            ));
        }
        match impossible {
            Some(why) => Err(self.invalid(format!("damaged or forged: {why}"))),
            None => Ok(()),
        }
    }
}

/// Why a pixel record cannot be one of a render whose pixels took at most `most` samples, if
/// it cannot: more samples, or sums beyond what its samples can add up to.
fn impossible_pixel(p: &Pixel, most: u32) -> Option<String> {
    if p.count > most {
        return Some(format!(
            "holds {} samples, its part at most {most}",
            p.count
        ));
    }
    // Samples are within MAX_SAMPLE = 2^31, in units of 2^-64: 2^95 units each at most.
    let bound = u128::from(p.count) << 95;
    if p.sum.iter().any(|s| s.unsigned_abs() > bound) {
        return Some(format!(
            "has sums beyond what its {} samples can add up to",
            p.count
        ));
    }
    if p.count == 0 && p.sum_sq.iter().any(|&q| q != 0) {
        return Some("has squares of samples it did not take".into());
    }
    // Cauchy-Schwarz: (sum x)^2 <= n sum x^2 for any samples; in units of 2^-64, with each
    // square's rounding (half a unit) allowed for. A saturated sum of squares bounds nothing.
    let n = f64::from(p.count);
    let squares_fit = |c: usize| {
        let (sum, sum_sq) = (p.sum[c] as f64, p.sum_sq[c]);
        sum_sq == u128::MAX || sum * sum <= n * (sum_sq as f64 + n) * ONE * (1.0 + 1e-9)
    };
    if !(0..3).all(squares_fit) {
        return Some(format!(
            "has sums that no {} samples with its sums of squares can have",
            p.count
        ));
    }
    None
}

fn encode(p: &Pixel) -> [u8; PIXEL_BYTES] {
    let mut out = [0u8; PIXEL_BYTES];
    out[..4].copy_from_slice(&p.count.to_le_bytes());
    for c in 0..3 {
        out[4 + 16 * c..20 + 16 * c].copy_from_slice(&p.sum[c].to_le_bytes());
        out[52 + 16 * c..68 + 16 * c].copy_from_slice(&p.sum_sq[c].to_le_bytes());
    }
    out
}

fn decode(b: &[u8; PIXEL_BYTES]) -> Pixel {
    let word = |at: usize| -> [u8; 16] { b[at..at + 16].try_into().expect("16 bytes") };
    Pixel {
        count: u32::from_le_bytes(b[..4].try_into().expect("4 bytes")),
        sum: std::array::from_fn(|c| i128::from_le_bytes(word(4 + 16 * c))),
        sum_sq: std::array::from_fn(|c| u128::from_le_bytes(word(52 + 16 * c))),
    }
}

fn encode_feature(f: &FeaturePixel) -> [u8; FEATURE_BYTES] {
    let mut out = [0u8; FEATURE_BYTES];
    out[..4].copy_from_slice(&f.count.to_le_bytes());
    for c in 0..3 {
        out[4 + 4 * c..8 + 4 * c].copy_from_slice(&f.albedo[c].to_le_bytes());
        out[16 + 4 * c..20 + 4 * c].copy_from_slice(&f.normal[c].to_le_bytes());
    }
    out
}

fn decode_feature(b: &[u8; FEATURE_BYTES]) -> FeaturePixel {
    let word = |at: usize| -> [u8; 4] { b[at..at + 4].try_into().expect("4 bytes") };
    FeaturePixel {
        count: u32::from_le_bytes(word(0)),
        albedo: std::array::from_fn(|c| i32::from_le_bytes(word(4 + 4 * c))),
        normal: std::array::from_fn(|c| i32::from_le_bytes(word(16 + 4 * c))),
    }
}

/// A reader or writer that keeps the CRC-32 of the bytes passing through.
struct Crc<T>(T, crc32fast::Hasher);

impl<T: Write> Write for Crc<T> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.0.write(buf)?;
        self.1.update(&buf[..n]);
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.0.flush()
    }
}

impl<T: Read> Read for Crc<T> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.0.read(buf)?;
        self.1.update(&buf[..n]);
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::splat::Splats;
    use fenestra_core::{Rgb, Vec3};

    fn header(film: &Film) -> FilmHeader {
        FilmHeader {
            key: "k".into(),
            samples: Some(SampleRange { start: 0, end: 4 }),
            window: film.window,
            stats: RenderStats {
                width: film.width,
                height: film.height,
                ..Default::default()
            },
            features: film.takes_features(),
        }
    }

    fn film(light_paths: u64) -> Film {
        let mut film = Film::new(5, 3);
        for (i, p) in film.pixels.iter_mut().enumerate() {
            for k in 0..4 {
                p.add(Rgb::new(i as f32, 0.5 * k as f32, 1.0));
            }
        }
        if light_paths > 0 {
            let mut splats = Splats::default();
            splats.add(4, 2, Rgb::new(2.0, 3.0, 4.0));
            splats.add(0, 1, Rgb::new(0.25, 0.0, 1.0));
            splats.add(4, 2, Rgb::new(1.0, 1.0, 1.0));
            splats.paths = light_paths;
            film.add_splats(&splats, None);
        }
        film
    }

    #[test]
    fn splats_and_light_paths_round_trip_and_add_into_a_film() {
        let dir = std::env::temp_dir().join(format!("fenestra-film-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("a.film");
        let a = film(7);
        write(&path, &header(&a), &a).expect("write");
        let (h, b) = read(&path).expect("read");
        assert_eq!(h, header(&a));
        assert_eq!(
            (b.pixels, b.splats, b.light_paths),
            (a.pixels.clone(), a.splats.clone(), 7)
        );
        // A film without light paths gathers the part's splats and counts its paths.
        let mut sum = film(0);
        add_into(&path, &mut sum).expect("add");
        assert_eq!(sum.light_paths, 7);
        assert_eq!(sum.splats, a.splats);
        // Without light paths the file holds no splat records: 100 bytes a pixel fewer.
        let plain = dir.join("plain.film");
        write(&plain, &header(&a), &film(0)).expect("write");
        let size = |p: &Path| std::fs::metadata(p).expect("size").len();
        assert_eq!(size(&path) - size(&plain), 15 * PIXEL_BYTES as u64);
        let (_, c) = read(&plain).expect("read");
        assert!(c.splats.is_empty() && c.light_paths == 0);
        // A count of light paths whose splats are not there is refused before they are read.
        let mut bytes = std::fs::read(&plain).expect("bytes");
        let at = 22 + serde_json::to_vec(&header(&a)).expect("json").len();
        bytes[at] = 1;
        let forged = dir.join("forged.film");
        std::fs::write(&forged, &bytes).expect("write");
        let e = read(&forged).expect_err("no splats").to_string();
        assert!(e.contains("truncated or corrupt"), "{e}");
        std::fs::remove_dir_all(&dir).expect("clean");
    }

    #[test]
    fn features_round_trip_add_into_a_film_that_takes_them_and_only_such() {
        use crate::features::Feature;
        let dir =
            std::env::temp_dir().join(format!("fenestra-film-features-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("f.film");
        let mut a = film(0).with_features();
        for (i, f) in a.features.iter_mut().enumerate() {
            f.add(&Feature {
                albedo: Rgb::new(0.25, i as f32 / 15.0, 1.0),
                normal: Vec3::new(0.0, -0.6, 0.8),
            });
        }
        write(&path, &header(&a), &a).expect("write");
        let (h, b) = read(&path).expect("read");
        assert!(h.features);
        assert_eq!(b.features, a.features);
        let mut sum = film(0).with_features();
        add_into(&path, &mut sum).expect("add");
        assert_eq!(sum.features, a.features);
        let e = add_into(&path, &mut film(0)).expect_err("a film without features");
        assert!(e.to_string().contains("holds denoising features"), "{e}");
        // A feature record of more samples than a pixel takes is refused.
        let mut bytes = std::fs::read(&path).expect("bytes");
        let first = bytes.len() - 4 - 15 * FEATURE_BYTES;
        bytes[first..first + 4].copy_from_slice(&(FEATURE_SAMPLES + 1).to_le_bytes());
        let crc = crc32fast::hash(&bytes[..bytes.len() - 4]);
        let n = bytes.len();
        bytes[n - 4..].copy_from_slice(&crc.to_le_bytes());
        let forged = dir.join("forged.film");
        std::fs::write(&forged, &bytes).expect("write");
        let e = read(&forged)
            .expect_err("too many feature samples")
            .to_string();
        assert!(e.contains("feature samples"), "{e}");
        std::fs::remove_dir_all(&dir).expect("clean");
    }

    /// A version-1 file (no light-path count, no splats) reads as a film without light paths.
    #[test]
    fn version_1_files_read_as_films_without_light_paths() {
        let a = film(0);
        let json = serde_json::to_vec(&header(&a)).expect("json");
        let mut bytes = MAGIC.to_vec();
        bytes.extend(1u32.to_le_bytes());
        bytes.extend((json.len() as u32).to_le_bytes());
        bytes.extend(&json);
        for p in &a.pixels {
            bytes.extend(encode(p));
        }
        let mut crc = crc32fast::Hasher::new();
        crc.update(&bytes);
        bytes.extend(crc.finalize().to_le_bytes());
        let path = std::env::temp_dir().join(format!("fenestra-v1-{}.film", std::process::id()));
        std::fs::write(&path, &bytes).expect("write");
        let (_, b) = read(&path).expect("version 1");
        std::fs::remove_file(&path).expect("clean");
        assert_eq!(b.pixels, a.pixels);
        assert!(b.splats.is_empty() && b.light_paths == 0);
    }
}
