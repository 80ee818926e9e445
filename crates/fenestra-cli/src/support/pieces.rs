//! Pieces of a render split across machines: sample ranges (`--samples A..B`) and tiles
//! (`--crop X0,Y0,X1,Y1`), read from the command line or cut for `fenestra split`.

use anyhow::{bail, Result};
use fenestra_render::driver::BLOCK_SIZE;
use fenestra_render::film::Window;
use fenestra_render::film_file::SampleRange;
use fenestra_session::Crop;

/// Reads `A..B` (sample indices A to B-1, A < B).
pub fn parse_samples(s: &str) -> Result<SampleRange> {
    let bad = || anyhow::anyhow!("bad --samples '{s}': expected A..B with A < B, e.g. 0..256");
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    let index = |v: &str| -> Result<u32> {
        let v = v.trim();
        if v.is_empty() || !v.bytes().all(|b| b.is_ascii_digit()) {
            bail!(bad());
        }
        v.parse()
            .map_err(|_| anyhow::anyhow!("--samples '{s}': sample indices go up to {}", u32::MAX))
    };
    let (start, end) = (index(a)?, index(b)?);
    if start >= end {
        bail!(bad());
    }
    Ok(SampleRange { start, end })
}

/// Reads `X0,Y0,X1,Y1` (columns X0 to X1-1, rows Y0 to Y1-1; the session checks them
/// against the image).
pub fn parse_crop(s: &str) -> Result<Crop> {
    let bad = || anyhow::anyhow!("bad --crop '{s}': expected X0,Y0,X1,Y1, e.g. 0,0,64,64");
    let v: Vec<u32> = s
        .split(',')
        .map(|t| t.trim().parse().map_err(|_| bad()))
        .collect::<Result<_>>()?;
    let [x0, y0, x1, y1] = v[..] else {
        bail!(bad())
    };
    Ok(Crop { x0, y0, x1, y1 })
}

/// `spp` samples cut into `parts` ranges of sizes that differ by at most one.
pub fn by_samples(spp: u32, parts: u32) -> Result<Vec<SampleRange>> {
    if parts == 0 || parts > spp {
        bail!("cannot cut {spp} samples per pixel into {parts} parts");
    }
    Ok((0..parts)
        .map(|i| SampleRange {
            start: cut(spp, parts, i),
            end: cut(spp, parts, i + 1),
        })
        .collect())
}

/// A `width` x `height` image cut into `parts` bands of rows, each a whole number of 8-pixel
/// block rows (the last takes the image's edge), of heights that differ by at most a block.
pub fn by_tiles(width: u32, height: u32, parts: u32) -> Result<Vec<Window>> {
    let rows = height.div_ceil(BLOCK_SIZE);
    if parts == 0 || parts > rows {
        bail!(
            "cannot cut a {width}x{height} image into {parts} bands of 8-pixel block rows (it has {rows})"
        );
    }
    let y = |i: u32| (cut(rows, parts, i) * BLOCK_SIZE).min(height);
    Ok((0..parts)
        .map(|i| Window {
            y0: y(i),
            y1: y(i + 1),
            ..Window::full(width, height)
        })
        .collect())
}

/// Where the `i`-th of `parts` even pieces of `n` begins.
fn cut(n: u32, parts: u32, i: u32) -> u32 {
    (u64::from(n) * u64::from(i) / u64::from(parts)) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_render::integrator::Split;

    #[test]
    fn sample_ranges_cover_every_sample_once() {
        let r = by_samples(1000, 7).expect("cut");
        assert_eq!(r[0].start, 0);
        assert_eq!(r[6].end, 1000);
        assert!(r.windows(2).all(|w| w[0].end == w[1].start));
        assert!(r.iter().all(|s| (142..=143).contains(&(s.end - s.start))));
        assert!(by_samples(4, 5).is_err());
        assert_eq!(parse_samples("16..32").expect("parse"), r_(16, 32));
        for bad in ["16", "32..16", "5..5", "a..b", "-1..3"] {
            let e = parse_samples(bad).expect_err(bad).to_string();
            assert!(e.contains("expected A..B with A < B"), "{bad}: {e}");
        }
        let e = parse_samples("0..99999999999")
            .expect_err("too many")
            .to_string();
        assert!(e.contains("sample indices go up to 4294967295"), "{e}");
    }

    fn r_(start: u32, end: u32) -> SampleRange {
        SampleRange { start, end }
    }

    #[test]
    fn tiles_cover_the_image_on_the_block_grid() {
        let t = by_tiles(100, 70, 3).expect("cut");
        assert_eq!((t[0].y0, t[2].y1), (0, 70));
        assert!(t.windows(2).all(|w| w[0].y1 == w[1].y0 && w[0].y1 % 8 == 0));
        assert!(t.iter().all(|w| (w.x0, w.x1) == (0, 100)));
        assert!(by_tiles(100, 70, 10).is_err());
        let window = |s: &str, split| {
            let crop = parse_crop(s).map_err(|e| e.to_string())?;
            crop.window(100, 70, split)
                .map_err(|e| e.worded(fenestra_session::Style::Flag))
        };
        let ok = window("8,16,100,70", Split::BlockTiles).expect("on the grid");
        assert_eq!((ok.x0, ok.y0, ok.x1, ok.y1), (8, 16, 100, 70));
        let err = window("4,16,100,70", Split::BlockTiles).expect_err("off the grid");
        assert!(err.starts_with("--crop 4,16,100,70: "), "{err}");
        assert!(err.contains("multiples of 8"), "{err}");
        assert!(window("4,16,100,70", Split::SamplesOrTiles).is_ok());
        for bad in ["0,0,101,70", "5,5,5,9", "1,2,3", "a,0,4,4"] {
            assert!(window(bad, Split::SamplesOrTiles).is_err(), "{bad}");
        }
    }
}
