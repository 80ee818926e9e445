//! A picture of an estimate (seed 000 Fig. 5.6): the fitted portals' outlines in black under
//! the photons coloured by cluster (noise in grey), projected on the XY, XZ and YZ planes side
//! by side, each with its axes in metres and the scene's bounding box in light grey. SVG,
//! drawn with plotters, so the axis labels need no font files.

use crate::error::PortalError;
use crate::estimate::Estimate;
use crate::portal::Portal;
use fenestra_core::fs::write_atomically;
use fenestra_core::palette::CATEGORIES;
use fenestra_core::Vec3;
use plotters::prelude::*;
use std::path::Path;

/// Pixels of one panel's plotting area, square so that the projections keep their shape.
const PANEL: u32 = 400;

const NOISE: RGBColor = RGBColor(190, 190, 190);
const BOUNDS: RGBColor = RGBColor(200, 200, 200);

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

/// Writes the three projections of `estimate` to `path` (SVG, atomically), framed by the
/// scene's bounding box `bounds`.
pub fn write_projections(
    estimate: &Estimate,
    bounds: (Vec3, Vec3),
    path: &Path,
) -> Result<(), PortalError> {
    let mut svg = String::new();
    let dots = draw(estimate, bounds, &mut svg).map_err(|e| PortalError::Plot(e.to_string()))?;
    // Thousands of photons as one path per colour of zero-length round-capped segments: a
    // tenth of the size of an element per dot.
    let mut layer = String::new();
    for (colour, path) in dots.iter().filter(|(_, p)| !p.is_empty()) {
        let RGBColor(r, g, b) = colour;
        layer.push_str(&format!(
            "<path d=\"{path}\" stroke=\"#{r:02x}{g:02x}{b:02x}\" stroke-width=\"2.5\" stroke-linecap=\"round\" fill=\"none\"/>\n"
        ));
    }
    let end = svg.rfind("</svg>").unwrap_or(svg.len());
    svg.insert_str(end, &layer);
    Ok(write_atomically(path, |tmp| std::fs::write(tmp, &svg))?)
}

/// Draws panels, axes, bounds and outlines into `svg`; returns the photons' dots as SVG path
/// data per colour, in picture coordinates.
fn draw<'a>(
    estimate: &Estimate,
    (lo3, hi3): (Vec3, Vec3),
    svg: &'a mut String,
) -> Result<Vec<(RGBColor, String)>, Box<dyn std::error::Error + 'a>> {
    let (label_x, label_y, caption) = (44, 60, 28);
    let size = (3 * (PANEL + label_y + 16), PANEL + label_x + caption + 16);
    let root = SVGBackend::with_string(svg, size).into_drawing_area();
    root.fill(&WHITE)?;
    // Dots by colour: one per cluster (by palette slot) and the noise.
    let mut dots: Vec<(RGBColor, String)> = CATEGORIES
        .iter()
        .map(|&[r, g, b]| RGBColor(r, g, b))
        .chain([NOISE])
        .map(|c| (c, String::new()))
        .collect();
    let mut slot = vec![CATEGORIES.len(); estimate.photons.points.len()];
    for (k, c) in estimate.clusters.iter().enumerate() {
        for &i in c {
            slot[i] = k % CATEGORIES.len();
        }
    }
    let outlines: Vec<Vec<Vec3>> = estimate
        .portals
        .iter()
        .map(|e| outline(&e.portal))
        .collect();
    let panels = root.split_evenly((1, 3));
    for (area, (axes, names)) in panels.iter().zip([
        ((0, 1), ("x", "y")),
        ((0, 2), ("x", "z")),
        ((1, 2), ("y", "z")),
    ]) {
        let project = |p: Vec3| (f64::from(p[axes.0]), f64::from(p[axes.1]));
        // A square window around everything drawn, so that lengths compare across axes.
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        let drawn = estimate
            .photons
            .points
            .iter()
            .chain(outlines.iter().flatten());
        for q in drawn.chain(&[lo3, hi3]).map(|&p| project(p)) {
            (lo[0], hi[0]) = (lo[0].min(q.0), hi[0].max(q.0));
            (lo[1], hi[1]) = (lo[1].min(q.1), hi[1].max(q.1));
        }
        let half = 0.55 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-6);
        let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!("{}{} projection", names.0, names.1).to_uppercase(),
                ("sans-serif", 16),
            )
            .margin(8)
            .x_label_area_size(label_x)
            .y_label_area_size(label_y)
            .build_cartesian_2d(mid[0] - half..mid[0] + half, mid[1] - half..mid[1] + half)?;
        // As many decimals as a tenth of the window needs; "+ 0.0" turns -0 into 0.
        let decimals = (-(0.2 * half).log10().floor()).max(0.0) as usize;
        let tick = |v: &f64| format!("{:.*}", decimals, v + 0.0);
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(format!("{} (m)", names.0))
            .y_desc(format!("{} (m)", names.1))
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .draw()?;
        let (a, b) = (project(lo3), project(hi3));
        chart.draw_series(std::iter::once(Rectangle::new(
            [a, b],
            BOUNDS.stroke_width(1),
        )))?;
        for o in &outlines {
            let closed = o.iter().chain(o.first()).map(|&p| project(p));
            chart.draw_series(std::iter::once(PathElement::new(
                closed.collect::<Vec<_>>(),
                BLACK.stroke_width(2),
            )))?;
        }
        for (p, &k) in estimate.photons.points.iter().zip(&slot) {
            let (x, y) = chart.backend_coord(&project(*p));
            dots[k].1.push_str(&format!("M{x} {y}h0"));
        }
    }
    root.present()?;
    Ok(dots)
}
