//! A picture of an estimate (seed 000 Fig. 5.6): the fitted portals' outlines in black under
//! the photons coloured by cluster (noise in grey), projected on the XY, XZ and YZ planes side by side.

use crate::error::PortalError;
use crate::estimate::Estimate;
use crate::portal::Portal;
use fenestra_core::fs::write_atomically;
use fenestra_core::Vec3;
use image::{Rgb, RgbImage};
use std::path::Path;

const PANEL: u32 = 420;
const MARGIN: u32 = 24;

const PALETTE: [[u8; 3]; 8] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [188, 189, 34],
];
const NOISE: [u8; 3] = [190, 190, 190];
const OUTLINE: [u8; 3] = [0, 0, 0];
const BOUNDS: [u8; 3] = [215, 215, 215];

/// Points along a portal's border (closed).
pub fn outline(p: &Portal) -> Vec<Vec3> {
    match p {
        Portal::Quad { corner, e1, e2 } => {
            vec![*corner, *corner + *e1, *corner + *e1 + *e2, *corner + *e2]
        }
        Portal::Triangle { vertices } => vertices.to_vec(),
        Portal::Ellipse { center, a, b } => (0..128)
            .map(|k| {
                let t = k as f32 / 128.0 * std::f32::consts::TAU;
                *center + *a * t.cos() + *b * t.sin()
            })
            .collect(),
    }
}

/// Writes the three projections of `estimate` to `path` (PNG, atomically), framed by the
/// scene's bounding box `bounds` (drawn in light grey).
pub fn write_projections(
    estimate: &Estimate,
    bounds: (Vec3, Vec3),
    path: &Path,
) -> Result<(), PortalError> {
    let (lo3, hi3) = bounds;
    let corners: Vec<Vec3> = (0..8)
        .map(|k| {
            Vec3::new(
                if k & 1 == 0 { lo3.x } else { hi3.x },
                if k & 2 == 0 { lo3.y } else { hi3.y },
                if k & 4 == 0 { lo3.z } else { hi3.z },
            )
        })
        .collect();
    let mut img = RgbImage::from_pixel(3 * PANEL + 4 * MARGIN, PANEL + 2 * MARGIN, Rgb([255; 3]));
    let mut colour = vec![NOISE; estimate.photons.points.len()];
    for (k, c) in estimate.clusters.iter().enumerate() {
        for &i in c {
            colour[i] = PALETTE[k % PALETTE.len()];
        }
    }
    let outlines: Vec<Vec<Vec3>> = estimate
        .portals
        .iter()
        .map(|e| outline(&e.portal))
        .collect();
    for (panel, (axes, name)) in [((0, 1), "XY"), ((0, 2), "XZ"), ((1, 2), "YZ")]
        .into_iter()
        .enumerate()
    {
        let x0 = MARGIN + panel as u32 * (PANEL + MARGIN);
        let project = |p: Vec3| [p[axes.0], p[axes.1]];
        let all = estimate
            .photons
            .points
            .iter()
            .chain(outlines.iter().flatten())
            .chain(&corners)
            .map(|&p| project(p));
        let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
        for q in all {
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-6) * 1.1;
        let mid = [(lo[0] + hi[0]) * 0.5, (lo[1] + hi[1]) * 0.5];
        let to_pixel = |p: Vec3| {
            let q = project(p);
            let s = PANEL as f32 / extent;
            (
                x0 as f32 + PANEL as f32 * 0.5 + (q[0] - mid[0]) * s,
                MARGIN as f32 + PANEL as f32 * 0.5 - (q[1] - mid[1]) * s,
            )
        };
        frame(&mut img, x0, MARGIN);
        let (a, b) = (to_pixel(lo3), to_pixel(hi3));
        for (p, q) in [
            ((a.0, a.1), (b.0, a.1)),
            ((b.0, a.1), (b.0, b.1)),
            ((b.0, b.1), (a.0, b.1)),
            ((a.0, b.1), (a.0, a.1)),
        ] {
            line(&mut img, p, q, BOUNDS);
        }
        label(&mut img, x0, MARGIN - 14, name);
        for o in &outlines {
            for k in 0..o.len() {
                let (a, b) = (to_pixel(o[k]), to_pixel(o[(k + 1) % o.len()]));
                line(&mut img, a, b, OUTLINE);
            }
        }
        for (p, c) in estimate.photons.points.iter().zip(&colour) {
            let (x, y) = to_pixel(*p);
            dot(&mut img, x, y, *c);
        }
    }
    Ok(write_atomically(path, |tmp| {
        img.save_with_format(tmp, image::ImageFormat::Png)
    })?)
}

fn put(img: &mut RgbImage, x: i64, y: i64, c: [u8; 3]) {
    if x >= 0 && y >= 0 && (x as u32) < img.width() && (y as u32) < img.height() {
        img.put_pixel(x as u32, y as u32, Rgb(c));
    }
}

fn dot(img: &mut RgbImage, x: f32, y: f32, c: [u8; 3]) {
    let (x, y) = (x.round() as i64, y.round() as i64);
    for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
        put(img, x + dx, y + dy, c);
    }
}

/// A 2-pixel-wide segment, stepped along its longer axis.
fn line(img: &mut RgbImage, a: (f32, f32), b: (f32, f32), c: [u8; 3]) {
    let steps = (b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil().max(1.0) as i64;
    for s in 0..=steps {
        let t = s as f32 / steps as f32;
        dot(img, a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t, c);
    }
}

fn frame(img: &mut RgbImage, x0: u32, y0: u32) {
    let grey = [120, 120, 120];
    for k in 0..=PANEL as i64 {
        for (x, y) in [(k, 0), (k, PANEL as i64), (0, k), (PANEL as i64, k)] {
            put(img, x0 as i64 + x, y0 as i64 + y, grey);
        }
    }
}

/// The axis names in a 5x7 bitmap font (X, Y and Z are all a label needs).
fn label(img: &mut RgbImage, x0: u32, y0: u32, text: &str) {
    const GLYPHS: [(char, [u8; 7]); 3] = [
        ('X', [0x11, 0x11, 0x0a, 0x04, 0x0a, 0x11, 0x11]),
        ('Y', [0x11, 0x11, 0x0a, 0x04, 0x04, 0x04, 0x04]),
        ('Z', [0x1f, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1f]),
    ];
    for (i, ch) in text.chars().enumerate() {
        let Some((_, rows)) = GLYPHS.iter().find(|(g, _)| *g == ch) else {
            continue;
        };
        for (r, bits) in rows.iter().enumerate() {
            for col in 0..5 {
                if bits & (0x10 >> col) != 0 {
                    let (x, y) = (x0 as i64 + i as i64 * 7 + col, y0 as i64 + r as i64);
                    put(img, x, y, [0, 0, 0]);
                }
            }
        }
    }
}
