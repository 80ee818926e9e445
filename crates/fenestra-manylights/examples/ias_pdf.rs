//! How ias's PDF adapts at a point over its passes (seed 004 Fig. 4.10): the PDFs over the
//! cut of the largest region of each given pixel of a 160x90 render, pass by pass, drawn as
//! an SVG (clusters on the horizontal axis, ordered by their probability in the last pass;
//! pass 0, uniform, left out as in the seed). Prints what it drew.
//!
//! cargo run --release -p fenestra-manylights --example ias_pdf -- SCENE OUT.svg X,Y [X,Y...]

use fenestra_builtin as builtin;
use fenestra_manylights::{Ias, IasOptions, PdfTrace};
use fenestra_render::{Integrator, RenderControl, RenderScene};
use fenestra_scene::{Backend, Scene};
use std::fmt::Write;

const WIDTH: u32 = 160;
const HEIGHT: u32 = 90;
/// One panel of the figure.
const PANEL: (f32, f32) = (420.0, 260.0);
const MARGIN: f32 = 50.0;
/// Line colours of passes 1, 2, ... (then repeated).
const COLOURS: [&str; 8] = [
    "#440154", "#3b528b", "#21918c", "#5ec962", "#fde725", "#f98e09", "#bc3754", "#57106e",
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [name, out, points @ ..] = args.as_slice() else {
        return Err("usage: ias_pdf SCENE OUT.svg X,Y [X,Y...]".into());
    };
    let scene = RenderScene::new(Scene::build(builtin::load(name)?, Backend::default())?);
    let mut ias = Ias::new(IasOptions::default())?;
    ias.prepare(&scene, &RenderControl::unattended())?;
    let mut traces = Vec::new();
    for point in points {
        let (x, y) = point
            .split_once(',')
            .and_then(|(x, y)| Some((x.parse().ok()?, y.parse().ok()?)))
            .filter(|&(x, y)| x < WIDTH && y < HEIGHT)
            .ok_or_else(|| {
                format!("a point is X,Y in pixels of a {WIDTH}x{HEIGHT} image, got '{point}'")
            })?;
        let trace = ias
            .pdf_trace(&scene, WIDTH, HEIGHT, 1, x, y)
            .ok_or_else(|| format!("pixel {x},{y} sees no surface"))?;
        println!(
            "{name} pixel ({x}, {y}): {} clusters in the cut, {} passes",
            trace.clusters.len(),
            trace.passes.len()
        );
        traces.push(((x, y), trace));
    }
    std::fs::write(out, svg(name, &traces))?;
    println!("wrote {out}");
    Ok(())
}

/// The figure: one panel per point, side by side.
fn svg(name: &str, traces: &[((u32, u32), PdfTrace)]) -> String {
    let w = traces.len() as f32 * (PANEL.0 + MARGIN) + MARGIN;
    let h = PANEL.1 + 2.0 * MARGIN + 20.0;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    for (k, ((x, y), trace)) in traces.iter().enumerate() {
        let left = MARGIN + k as f32 * (PANEL.0 + MARGIN);
        let top = MARGIN;
        let last = trace.passes.last().cloned().unwrap_or_default();
        let mut order: Vec<usize> = (0..last.len()).collect();
        order.sort_by(|&a, &b| last[b].total_cmp(&last[a]).then(a.cmp(&b)));
        let shown = &trace.passes[1.min(trace.passes.len())..];
        let top_p = shown
            .iter()
            .flatten()
            .fold(0.0f32, |m, &p| m.max(p))
            .max(1e-6);
        let n = order.len().max(2) as f32;
        let _ = writeln!(
            s,
            "<text x=\"{left}\" y=\"{}\">{name}, pixel ({x}, {y}): {} clusters, {} passes</text>",
            top - 12.0,
            order.len(),
            trace.passes.len()
        );
        let _ = writeln!(
            s,
            "<rect x=\"{left}\" y=\"{top}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#888\"/>",
            PANEL.0, PANEL.1
        );
        for (pass, pdf) in shown.iter().enumerate() {
            let mut path = String::new();
            for (i, &c) in order.iter().enumerate() {
                let px = left + i as f32 / (n - 1.0) * PANEL.0;
                let py = top + PANEL.1 * (1.0 - pdf[c] / top_p);
                let _ = write!(path, "{}{px:.1},{py:.1}", if i == 0 { "M" } else { " L" });
            }
            let colour = COLOURS[pass % COLOURS.len()];
            let _ = writeln!(
                s,
                "<path d=\"{path}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.5\"/>"
            );
            let _ = writeln!(
                s,
                "<text x=\"{}\" y=\"{}\" fill=\"{colour}\">pass {}</text>",
                left + PANEL.0 - 60.0,
                top + 16.0 + 14.0 * pass as f32,
                pass + 1
            );
        }
        let _ = writeln!(
            s,
            "<text x=\"{left}\" y=\"{}\">clusters, by probability in the last pass</text>",
            top + PANEL.1 + 16.0
        );
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" transform=\"rotate(-90 {0} {1})\">probability (0 to {top_p:.3})</text>",
            left - 8.0,
            top + PANEL.1
        );
    }
    s.push_str("</svg>\n");
    s
}
