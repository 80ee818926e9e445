//! Portable Float Map (PFM) input: the float image format pbrt-v4 scenes use for
//! environment maps. A text header, `PF` (RGB) or `Pf` (grey), the width and height, and a
//! scale whose sign gives the byte order (negative: little-endian) and whose magnitude
//! multiplies the values (as pbrt-v4 reads it), then exactly one whitespace byte and the
//! rows as 32-bit floats, bottom row first. No crate we use reads it; the format is this
//! page long.

use super::Image;
use crate::Rgb;

/// Why bytes are not a PFM image.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum PfmError {
    /// The header stops before one of its words.
    #[error("the header ends before its {0}")]
    EndsBefore(&'static str),
    /// The header stops right after one of its words.
    #[error("the header ends after its {0}")]
    EndsAfter(&'static str),
    /// A word of the header is not text.
    #[error("its {0} is not text")]
    NotText(&'static str),
    /// The first word is not PF or Pf.
    #[error("not a PFM file (starts with {0:?}, not PF or Pf)")]
    NotPfm(String),
    /// The width or height is not a positive whole number.
    #[error("{what} {word:?} is not a positive whole number")]
    Size {
        /// "width" or "height".
        what: &'static str,
        /// What the header says.
        word: String,
    },
    /// The scale is zero or not a finite number.
    #[error("scale {0:?} is not a finite non-zero number")]
    Scale(String),
    /// The file holds fewer bytes than the pixels it declares.
    #[error("{width}x{height} pixels of {channels} floats need more than the {available} bytes after the header")]
    Truncated {
        /// Declared width.
        width: usize,
        /// Declared height.
        height: usize,
        /// Floats per pixel.
        channels: usize,
        /// Bytes after the header.
        available: usize,
    },
}

/// Decodes a PFM file's bytes.
pub fn decode(bytes: &[u8]) -> Result<Image, PfmError> {
    let mut rest = bytes;
    let mut token = |what: &'static str| -> Result<&str, PfmError> {
        let start = rest
            .iter()
            .position(|b| !b.is_ascii_whitespace())
            .ok_or(PfmError::EndsBefore(what))?;
        let len = rest[start..]
            .iter()
            .position(|b| b.is_ascii_whitespace())
            .ok_or(PfmError::EndsAfter(what))?;
        let word =
            std::str::from_utf8(&rest[start..start + len]).map_err(|_| PfmError::NotText(what))?;
        // The one whitespace byte after the token belongs to the header.
        rest = &rest[start + len + 1..];
        Ok(word)
    };
    let channels = match token("type")? {
        "PF" => 3,
        "Pf" => 1,
        other => return Err(PfmError::NotPfm(other.to_string())),
    };
    let mut size = |what: &'static str| -> Result<usize, PfmError> {
        let word = token(what)?;
        match word.parse::<usize>() {
            Ok(n) if n > 0 => Ok(n),
            _ => Err(PfmError::Size {
                what,
                word: word.to_string(),
            }),
        }
    };
    let width = size("width")?;
    let height = size("height")?;
    let word = token("scale")?;
    let scale = match word.parse::<f32>() {
        Ok(s) if s.is_finite() && s != 0.0 => s,
        _ => return Err(PfmError::Scale(word.to_string())),
    };
    let bytes_needed = width
        .checked_mul(height)
        .and_then(|n| n.checked_mul(channels * 4));
    if bytes_needed.is_none_or(|n| n > rest.len()) {
        return Err(PfmError::Truncated {
            width,
            height,
            channels,
            available: rest.len(),
        });
    }
    let magnitude = scale.abs();
    let value = |i: usize| {
        let b = [
            rest[4 * i],
            rest[4 * i + 1],
            rest[4 * i + 2],
            rest[4 * i + 3],
        ];
        magnitude
            * if scale < 0.0 {
                f32::from_le_bytes(b)
            } else {
                f32::from_be_bytes(b)
            }
    };
    let mut image = Image::new(width, height);
    for y in 0..height {
        // Rows are stored bottom first.
        let row = (height - 1 - y) * width;
        for x in 0..width {
            let i = (row + x) * channels;
            let c = if channels == 3 {
                Rgb::new(value(i), value(i + 1), value(i + 2))
            } else {
                Rgb::splat(value(i))
            };
            image.set(x, y, c);
        }
    }
    Ok(image)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pfm(header: &str, floats: &[f32], little: bool) -> Vec<u8> {
        let mut bytes = header.as_bytes().to_vec();
        for f in floats {
            bytes.extend(if little {
                f.to_le_bytes()
            } else {
                f.to_be_bytes()
            });
        }
        bytes
    }

    #[test]
    fn reads_both_byte_orders_bottom_row_first() {
        // 2x2 RGB: bottom row (1, 2), top row (3, 4), each pixel (v, v + 0.5, -v).
        let floats: Vec<f32> = [1.0f32, 2.0, 3.0, 4.0]
            .iter()
            .flat_map(|&v| [v, v + 0.5, -v])
            .collect();
        for (header, little) in [("PF\n2 2\n-1.0\n", true), ("PF\n2 2\n1.0\n", false)] {
            let img = decode(&pfm(header, &floats, little)).expect("decodes");
            assert_eq!((img.width, img.height), (2, 2));
            assert_eq!(img.get(0, 0), Rgb::new(3.0, 3.5, -3.0), "{header:?}");
            assert_eq!(img.get(1, 0), Rgb::new(4.0, 4.5, -4.0));
            assert_eq!(img.get(0, 1), Rgb::new(1.0, 1.5, -1.0));
            assert_eq!(img.get(1, 1), Rgb::new(2.0, 2.5, -2.0));
        }
        // Grey, with the scale's magnitude applied and the header on one line.
        let img = decode(&pfm("Pf 3 1 -2.0\n", &[1.0, 0.25, 8.0], true)).expect("grey");
        assert_eq!(img.pixels, [2.0, 0.5, 16.0].map(Rgb::splat));
    }

    #[test]
    fn bad_files_are_explained() {
        let one = [1.0f32, 1.0, 1.0];
        for (bytes, says) in [
            (pfm("P6\n1 1\n255\n", &[], true), "not a PFM file"),
            (pfm("PF\n1 x\n-1\n", &one, true), "height \"x\""),
            (pfm("PF\n0 1\n-1\n", &one, true), "width \"0\""),
            (pfm("PF\n1 1\nnan\n", &one, true), "scale \"nan\""),
            (
                pfm("PF\n2 1\n-1\n", &one, true),
                "need more than the 12 bytes",
            ),
            (
                pfm("PF\n4294967296 4294967296\n-1\n", &one, true),
                "need more than",
            ),
            (b"PF\n1 1".to_vec(), "ends after its height"),
            (b"PF\n1 1\n-1".to_vec(), "ends after its scale"),
        ] {
            let e = decode(&bytes).expect_err(says).to_string();
            assert!(e.contains(says), "{says}: {e}");
        }
    }
}
