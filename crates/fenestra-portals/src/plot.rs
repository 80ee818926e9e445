//! A picture of an estimate (seed 000 Fig. 5.6): the fitted portals' outlines in black under
//! the photons coloured by cluster (noise in grey), projected on the XY, XZ and YZ planes side
//! by side, each framed on the photons with its axes in metres and the scene's bounding box in
//! light grey. SVG, drawn with plotters, so the axis labels need no font files. And the
//! portals over the scene as its camera sees it (PNG).

use crate::error::PortalError;
use crate::estimate::Estimate;
use crate::portal::Portal;
use fenestra_core::fs::write_atomically;
use fenestra_core::image::{srgb_to_linear, Image};
use fenestra_core::palette::CATEGORIES;
use fenestra_core::{Rgb, Vec2, Vec3};
use fenestra_scene::Scene;
use plotters::prelude::*;
use rayon::prelude::*;
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
        // With no photon and no portal (nothing found) the scene's bounds, and a window
        // always, whatever the points (a chart's range is never NaN).
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        let photons_and_portals = estimate
            .photons
            .points
            .iter()
            .chain(outlines.iter().flatten());
        let mut drawn: Vec<Vec3> = photons_and_portals
            .filter(|p| p.is_finite())
            .copied()
            .collect();
        if drawn.is_empty() {
            drawn = [lo3, hi3].into_iter().filter(|p| p.is_finite()).collect();
        }
        for q in drawn.into_iter().map(project) {
            (lo[0], hi[0]) = (lo[0].min(q.0), hi[0].max(q.0));
            (lo[1], hi[1]) = (lo[1].min(q.1), hi[1].max(q.1));
        }
        if !(lo[0] <= hi[0] && lo[1] <= hi[1]) {
            (lo, hi) = ([-1.0; 2], [1.0; 2]);
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
        // The scene's bounds, clipped to the window (a ground plane's reach far beyond it).
        let clip = |(x, y): (f64, f64)| {
            (
                x.clamp(mid[0] - half, mid[0] + half),
                y.clamp(mid[1] - half, mid[1] + half),
            )
        };
        let (a, b) = (clip(project(lo3)), clip(project(hi3)));
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

/// Width in pixels of [`write_view`]'s picture.
const VIEW_WIDTH: u32 = 640;
/// Opacity of a portal's colour where it lies in front of the geometry (or on it), and where
/// it lies behind it (seen through the walls, fainter).
const IN_FRONT: f32 = 0.55;
const BEHIND: f32 = 0.18;

/// Writes the estimated portals over the scene as its camera sees it to `path` (PNG): the
/// geometry in grey shaded by the angle it is seen at, the sky in pale blue, each portal in
/// its cluster's colour (fainter where a wall hides it) with its outline: a picture in which a
/// user checks in seconds that the portals sit on the windows.
pub fn write_view(scene: &Scene, estimate: &Estimate, path: &Path) -> Result<(), PortalError> {
    let (w, h) = (scene.defaults.width.max(1), scene.defaults.height.max(1));
    let (vw, vh) = (
        VIEW_WIDTH,
        ((VIEW_WIDTH as u64 * h as u64 / w as u64) as u32).max(1),
    );
    let portals: Vec<&Portal> = estimate.portals.iter().map(|e| &e.portal).collect();
    // Per pixel: the shaded grey and the nearest portal in front (or, failing that, behind).
    let pixels: Vec<(f32, Option<(usize, bool)>)> = (0..vw * vh)
        .into_par_iter()
        .map(|k| {
            let film = Vec2::new(
                ((k % vw) as f32 + 0.5) * w as f32 / vw as f32,
                ((k / vw) as f32 + 0.5) * h as f32 / vh as f32,
            );
            let ray = scene.camera.generate_ray(film, w, h);
            let hit = scene.intersect(&ray, f32::INFINITY);
            let (grey, t_hit) = match &hit {
                Some(hit) => {
                    let si = scene.interaction(&ray, hit);
                    (0.08 + 0.6 * si.ns.dot(ray.d).abs(), hit.t)
                }
                None => (-1.0, f32::INFINITY),
            };
            let nearest = portals
                .iter()
                .enumerate()
                .filter_map(|(i, p)| p.intersect(ray.o, ray.d).map(|t| (i, t)))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(i, t)| (i, t <= t_hit * 1.01 + 1e-3));
            (grey, nearest)
        })
        .collect();
    let sky = Rgb::new(0.45, 0.6, 0.8);
    let mut image = Image::new(vw as usize, vh as usize);
    for (k, (grey, portal)) in pixels.iter().enumerate() {
        let base = if *grey < 0.0 { sky } else { Rgb::splat(*grey) };
        let (x, y) = ((k as u32 % vw) as i64, (k as u32 / vw) as i64);
        // An outline where a neighbour holds another portal (or none).
        let edge = portal.is_some()
            && [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)]
                .iter()
                .any(|(dx, dy)| {
                    let (nx, ny) = (x + dx, y + dy);
                    nx < 0
                        || ny < 0
                        || nx >= vw as i64
                        || ny >= vh as i64
                        || pixels[(ny * vw as i64 + nx) as usize].1.map(|p| p.0)
                            != portal.map(|p| p.0)
                });
        image.pixels[k] = match portal {
            Some((i, front)) => {
                let [r, g, b] = fenestra_core::palette::category(estimate.portals[*i].cluster);
                let colour = Rgb::new(
                    srgb_to_linear(r as f32 / 255.0),
                    srgb_to_linear(g as f32 / 255.0),
                    srgb_to_linear(b as f32 / 255.0),
                );
                let alpha = match (edge, front) {
                    (true, _) => 1.0,
                    (false, true) => IN_FRONT,
                    (false, false) => BEHIND,
                };
                base * (1.0 - alpha) + colour * alpha
            }
            None => base,
        };
    }
    image
        .write_png_to(path, Some(0.0))
        .map_err(|e| PortalError::Plot(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aim::Surroundings;
    use crate::estimate::Timings;
    use crate::photon::{Deposit, Photons};

    /// An estimate that found nothing: no photon, no cluster, no portal.
    fn nothing_found() -> Estimate {
        Estimate {
            photons: Photons {
                points: Vec::new(),
                beams: 0,
                rays: 0,
                deposit: Deposit::Depth,
                target: 8192,
                interrupted: false,
                settled: false,
                timed_out: false,
            },
            clusters: Vec::new(),
            portals: Vec::new(),
            timings: Timings::default(),
            surroundings: Surroundings {
                points: Vec::new(),
                sphere: (Vec3::ZERO, 1.0),
            },
        }
    }

    #[test]
    fn an_estimate_that_found_nothing_is_drawn_in_the_scenes_bounds() {
        let dir = std::env::temp_dir().join(format!("fenestra-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a folder");
        let path = dir.join("nothing.svg");
        let scene = (Vec3::splat(-2.0), Vec3::splat(3.0));
        write_projections(&nothing_found(), scene, &path).expect("drawn in the bounds");
        let svg = std::fs::read_to_string(&path).expect("written");
        assert!(svg.contains("XY PROJECTION"), "{svg}");
        // An empty scene's bounds are infinite: a unit window, still no panic.
        let empty = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        write_projections(&nothing_found(), empty, &path).expect("a unit window");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
