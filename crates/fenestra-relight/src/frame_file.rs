//! A precomputed frame on disk (`.rlf`), read back exactly as written (subspaces and
//! coefficients as f32):
//!
//! ```text
//! magic    "FENESTRA-RELIGHT\n"                     17 bytes
//! version  u32 little-endian (1)
//! length   u32 little-endian: bytes of the header
//! header   JSON (FrameHeader): size, gather samples, clusters' dimensions, statistics
//! clusters per cluster: its mean, then its directions, each of the padded gather length,
//!          f32 little-endian
//! pixels   row-major; per pixel its cluster u32 (u32::MAX: none), then if it has one its
//!          colour (3 f32) and its coefficients (the cluster's dimension, f32)
//! crc      u32 little-endian: CRC-32 of every byte before it
//! ```

use crate::frame::{FrameTransfer, Pixel};
use crate::haar;
use fenestra_core::Rgb;
use fenestra_lpca::Subspace;
use serde::{Deserialize, Serialize};
use std::path::Path;

const MAGIC: &[u8; 17] = b"FENESTRA-RELIGHT\n";
const VERSION: u32 = 1;

/// What a frame file says about itself.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameHeader {
    pub width: u32,
    pub height: u32,
    pub gather: usize,
    /// Each cluster's dimension.
    pub dimensions: Vec<u32>,
    pub explored: usize,
    pub rays: u64,
    /// Seconds the precomputation took.
    pub seconds: f64,
}

/// A frame file that cannot be read: where and why.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {reason}")]
pub struct FrameFileError {
    pub path: String,
    pub reason: String,
}

/// `frame`'s bytes, `seconds` its precomputation time.
pub fn encode(frame: &FrameTransfer, seconds: f64) -> Vec<u8> {
    let header = FrameHeader {
        width: frame.width,
        height: frame.height,
        gather: frame.gather,
        dimensions: frame
            .clusters
            .iter()
            .map(|c| c.basis.len() as u32)
            .collect(),
        explored: frame.explored,
        rays: frame.rays,
        seconds,
    };
    let json = serde_json::to_vec(&header).unwrap_or_default();
    let mut out = Vec::new();
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&json);
    let put = |out: &mut Vec<u8>, x: f32| out.extend_from_slice(&x.to_le_bytes());
    for c in &frame.clusters {
        for v in std::iter::once(&c.mean).chain(&c.basis) {
            v.iter().for_each(|&x| put(&mut out, x as f32));
        }
    }
    for p in &frame.pixels {
        match p {
            None => out.extend_from_slice(&u32::MAX.to_le_bytes()),
            Some(p) => {
                out.extend_from_slice(&p.cluster.to_le_bytes());
                [p.colour.r, p.colour.g, p.colour.b]
                    .into_iter()
                    .chain(p.coefficients.iter().copied())
                    .for_each(|x| put(&mut out, x));
            }
        }
    }
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// Writes `frame` to `path` (atomically: an interrupted write leaves no file).
pub fn write(
    path: &Path,
    frame: &FrameTransfer,
    seconds: f64,
) -> Result<(), fenestra_core::fs::WriteError> {
    let bytes = encode(frame, seconds);
    fenestra_core::fs::write_atomically(path, |tmp| std::fs::write(tmp, &bytes))
}

/// Reads the frame file at `path`, checked whole.
pub fn read(path: &Path) -> Result<(FrameHeader, FrameTransfer), FrameFileError> {
    let bytes = std::fs::read(path).map_err(|e| FrameFileError {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    decode(&bytes).map_err(|reason| FrameFileError {
        path: path.display().to_string(),
        reason,
    })
}

/// Reads a frame from its bytes.
pub fn decode(bytes: &[u8]) -> Result<(FrameHeader, FrameTransfer), String> {
    if bytes.len() < MAGIC.len() + 12 || &bytes[..MAGIC.len()] != MAGIC {
        return Err("not a relighting frame file".into());
    }
    let (body, crc) = bytes.split_at(bytes.len() - 4);
    if crc32fast::hash(body) != u32::from_le_bytes([crc[0], crc[1], crc[2], crc[3]]) {
        return Err("damaged (checksum mismatch)".into());
    }
    let mut r = Reader(&body[MAGIC.len()..]);
    let version = r.u32()?;
    if version != VERSION {
        return Err(format!("version {version}, this build reads {VERSION}"));
    }
    let length = r.u32()? as usize;
    let header: FrameHeader =
        serde_json::from_slice(r.take(length)?).map_err(|e| format!("header: {e}"))?;
    let n = haar::padded_len(header.gather);
    let vector = |r: &mut Reader| -> Result<Vec<f64>, String> {
        (0..n).map(|_| r.f32().map(f64::from)).collect()
    };
    let mut clusters = Vec::with_capacity(header.dimensions.len());
    for &d in &header.dimensions {
        let mean = vector(&mut r)?;
        let basis = (0..d).map(|_| vector(&mut r)).collect::<Result<_, _>>()?;
        clusters.push(Subspace { mean, basis });
    }
    let count = header.width as usize * header.height as usize;
    let mut pixels = Vec::with_capacity(count);
    for _ in 0..count {
        let c = r.u32()?;
        if c == u32::MAX {
            pixels.push(None);
            continue;
        }
        let d = *header
            .dimensions
            .get(c as usize)
            .ok_or_else(|| format!("pixel names cluster {c} of {}", clusters.len()))?;
        let colour = Rgb::new(r.f32()?, r.f32()?, r.f32()?);
        let coefficients = (0..d).map(|_| r.f32()).collect::<Result<_, _>>()?;
        pixels.push(Some(Pixel {
            cluster: c,
            coefficients,
            colour,
        }));
    }
    if !r.0.is_empty() {
        return Err(format!("{} bytes after the pixels", r.0.len()));
    }
    let frame = FrameTransfer {
        width: header.width,
        height: header.height,
        gather: header.gather,
        clusters,
        pixels,
        explored: header.explored,
        rays: header.rays,
    };
    Ok((header, frame))
}

/// Little-endian reads off a byte slice; running out is an error.
struct Reader<'a>(&'a [u8]);

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        if self.0.len() < n {
            return Err("truncated".into());
        }
        let (a, b) = self.0.split_at(n);
        self.0 = b;
        Ok(a)
    }
    fn u32(&mut self) -> Result<u32, String> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn f32(&mut self) -> Result<f32, String> {
        self.u32().map(f32::from_bits)
    }
}
