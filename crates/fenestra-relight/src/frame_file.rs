//! A precomputed frame on disk (`.rlf`), read back exactly as written (subspaces and
//! coefficients as f32):
//!
//! ```text
//! magic    "FENESTRA-RELIGHT\n"                     17 bytes
//! version  u32 little-endian (2; version 1, without kept pixels, is read too)
//! length   u32 little-endian: bytes of the header
//! header   JSON (FrameHeader): size, gather samples, clusters' dimensions, statistics
//! clusters per cluster: its mean, then its directions, each of the padded gather length,
//!          f32 little-endian
//! pixels   row-major; per pixel its cluster u32 (u32::MAX: none), then if it has one its
//!          colour (3 f32) and its coefficients (the cluster's dimension, f32); a kept pixel
//!          (u32::MAX - 1) its colour, its count of wavelet coefficients u32, and per
//!          coefficient its index u32 and its value f32
//! crc      u32 little-endian: CRC-32 of every byte before it
//! ```

use crate::frame::{FrameTransfer, Pixel, Transfer};
use crate::haar;
use fenestra_core::Rgb;
use fenestra_lpca::Subspace;
use serde::{Deserialize, Serialize};
use std::path::Path;

const MAGIC: &[u8; 17] = b"FENESTRA-RELIGHT\n";
const VERSION: u32 = 2;
/// A pixel's cluster field when it has none, and when its transfer is kept uncompressed.
const NONE: u32 = u32::MAX;
const KEPT: u32 = u32::MAX - 1;

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
            None => out.extend_from_slice(&NONE.to_le_bytes()),
            Some(p) => {
                let colour = [p.colour.r, p.colour.g, p.colour.b];
                match &p.transfer {
                    Transfer::Compressed {
                        cluster,
                        coefficients,
                    } => {
                        out.extend_from_slice(&cluster.to_le_bytes());
                        (colour.into_iter().chain(coefficients.iter().copied()))
                            .for_each(|x| put(&mut out, x));
                    }
                    Transfer::Kept { indices, values } => {
                        out.extend_from_slice(&KEPT.to_le_bytes());
                        colour.into_iter().for_each(|x| put(&mut out, x));
                        out.extend_from_slice(&(indices.len() as u32).to_le_bytes());
                        for (&i, &v) in indices.iter().zip(values) {
                            out.extend_from_slice(&i.to_le_bytes());
                            put(&mut out, v);
                        }
                    }
                }
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
    decode(&bytes).map_err(|problem| FrameFileError {
        path: path.display().to_string(),
        reason: problem.to_string(),
    })
}

/// Reads a frame from its bytes.
fn decode(bytes: &[u8]) -> Result<(FrameHeader, FrameTransfer), Damage> {
    if bytes.len() < MAGIC.len() + 12 || &bytes[..MAGIC.len()] != MAGIC {
        return Err(Damage::NotAFrame);
    }
    let (body, crc) = bytes.split_at(bytes.len() - 4);
    if crc32fast::hash(body) != u32::from_le_bytes([crc[0], crc[1], crc[2], crc[3]]) {
        return Err(Damage::Checksum);
    }
    let mut r = Reader(&body[MAGIC.len()..]);
    let version = r.u32()?;
    if version != VERSION && version != 1 {
        return Err(Damage::Version(version));
    }
    let length = r.u32()? as usize;
    let header: FrameHeader =
        serde_json::from_slice(r.take(length)?).map_err(|e| Damage::Header(e.to_string()))?;
    let n = haar::padded_len(header.gather);
    let vector = |r: &mut Reader| -> Result<Vec<f64>, Damage> {
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
        if c == NONE {
            pixels.push(None);
            continue;
        }
        let colour = Rgb::new(r.f32()?, r.f32()?, r.f32()?);
        let transfer = if c == KEPT && version > 1 {
            let n = r.u32()? as usize;
            // No more coefficients than the padded length: a count read from a damaged or
            // foreign file must not size an allocation.
            if n > haar::padded_len(header.gather) {
                return Err(Damage::KeptCount {
                    count: n,
                    gather: header.gather,
                });
            }
            let (mut indices, mut values) = (Vec::with_capacity(n), Vec::with_capacity(n));
            for _ in 0..n {
                let i = r.u32()?;
                if i as usize >= haar::padded_len(header.gather) {
                    return Err(Damage::KeptIndex(i));
                }
                indices.push(i);
                values.push(r.f32()?);
            }
            Transfer::Kept { indices, values }
        } else {
            let d = *header.dimensions.get(c as usize).ok_or(Damage::Cluster {
                cluster: c,
                clusters: clusters.len(),
            })?;
            let coefficients = (0..d).map(|_| r.f32()).collect::<Result<_, _>>()?;
            Transfer::Compressed {
                cluster: c,
                coefficients,
            }
        };
        pixels.push(Some(Pixel { transfer, colour }));
    }
    if !r.0.is_empty() {
        return Err(Damage::Trailing(r.0.len()));
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

/// Why bytes are not a frame file this build reads.
#[derive(Debug, thiserror::Error)]
enum Damage {
    #[error("not a relighting frame file")]
    NotAFrame,
    #[error("damaged (checksum mismatch)")]
    Checksum,
    #[error("version {0}, this build reads 1 and {VERSION}")]
    Version(u32),
    #[error("header: {0}")]
    Header(String),
    #[error("kept pixel with {count} coefficients of {gather}")]
    KeptCount { count: usize, gather: usize },
    #[error("kept pixel's coefficient {0} beyond the gather samples")]
    KeptIndex(u32),
    #[error("pixel names cluster {cluster} of {clusters}")]
    Cluster { cluster: u32, clusters: usize },
    #[error("{0} bytes after the pixels")]
    Trailing(usize),
    #[error("truncated")]
    Truncated,
}

/// Little-endian reads off a byte slice; running out is an error.
struct Reader<'a>(&'a [u8]);

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], Damage> {
        if self.0.len() < n {
            return Err(Damage::Truncated);
        }
        let (a, b) = self.0.split_at(n);
        self.0 = b;
        Ok(a)
    }
    fn u32(&mut self) -> Result<u32, Damage> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn f32(&mut self) -> Result<f32, Damage> {
        self.u32().map(f32::from_bits)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame() -> FrameTransfer {
        let pixel = |transfer| {
            Some(Pixel {
                transfer,
                colour: Rgb::new(0.25, 0.5, 0.75),
            })
        };
        FrameTransfer {
            width: 3,
            height: 1,
            gather: 3,
            clusters: vec![Subspace {
                mean: vec![0.5, -1.0, 2.0, 0.0],
                basis: vec![vec![1.0, 0.0, 0.0, 0.0], vec![0.0, 0.0, 0.0, 1.0]],
            }],
            pixels: vec![
                pixel(Transfer::Compressed {
                    cluster: 0,
                    coefficients: vec![0.125, -3.0],
                }),
                None,
                pixel(Transfer::Kept {
                    indices: vec![0, 3],
                    values: vec![1.5, -0.25],
                }),
            ],
            explored: 2,
            rays: 17,
        }
    }

    #[test]
    fn frames_read_back_as_written() {
        let bytes = encode(&frame(), 1.5);
        let (header, back) = decode(&bytes).expect("decode");
        assert_eq!(header.seconds, 1.5);
        assert_eq!(back.pixels, frame().pixels);
        assert_eq!(back.clusters, frame().clusters);
        assert_eq!((back.explored, back.rays), (2, 17));
    }

    #[test]
    fn damaged_and_malformed_frames_are_refused() {
        let mut bytes = encode(&frame(), 1.5);
        let last = bytes.len() - 9;
        bytes[last] ^= 1;
        let err = decode(&bytes).expect_err("a flipped byte").to_string();
        assert_eq!(err, "damaged (checksum mismatch)");
        // A kept pixel naming a coefficient past the padded length, checksum made right.
        let mut f = frame();
        f.pixels[2] = Some(Pixel {
            transfer: Transfer::Kept {
                indices: vec![4],
                values: vec![1.0],
            },
            colour: Rgb::ONE,
        });
        let err = decode(&encode(&f, 0.0))
            .expect_err("a coefficient out of range")
            .to_string();
        assert!(err.contains("coefficient 4 beyond"), "{err}");
        // More coefficients than the padded length.
        f.pixels[2] = Some(Pixel {
            transfer: Transfer::Kept {
                indices: vec![0; 5],
                values: vec![1.0; 5],
            },
            colour: Rgb::ONE,
        });
        let err = decode(&encode(&f, 0.0))
            .expect_err("too many coefficients")
            .to_string();
        assert!(err.contains("kept pixel with 5 coefficients"), "{err}");
    }
}
