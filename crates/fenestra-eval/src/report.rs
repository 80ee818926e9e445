//! A suite's report folder: results.json, table.md and an offline index.html with the
//! images side by side, zoomed crops, false-colour error maps and log-log convergence plots.

use crate::colormap::write_error_map;
use crate::plot::{loglog, Series};
use crate::run::{ReferenceRecord, RunRecord};
use crate::suite::Suite;
use crate::EvalError;
use fenestra_core::fs::slug;
use fenestra_core::fs::write_text_atomically;
use fenestra_core::image::Image;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// Mean and sample standard deviation.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Spread {
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation.
    pub sd: f64,
}

impl Spread {
    fn of(xs: &[f64]) -> Spread {
        let n = xs.len().max(1) as f64;
        let mean = xs.iter().sum::<f64>() / n;
        let sd = if xs.len() > 1 {
            (xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
        } else {
            0.0
        };
        Spread { mean, sd }
    }
}

/// One technique under one budget, over its repetitions.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// The technique's label.
    pub technique: String,
    /// Repetitions.
    pub runs: usize,
    /// Mean samples per pixel.
    pub spp: f64,
    /// Time in all, preparation (such as portal estimation) included.
    pub time_s: Spread,
    /// Mean seconds of preparation within `time_s`.
    pub prepare_s: f64,
    /// Mean squared error.
    pub mse: Spread,
    /// Relative mean squared error.
    pub rel_mse: Spread,
    /// Mean over repetitions of 1 / (MSE x time).
    pub efficiency: f64,
    /// Efficiency over the baseline's (the suite's first technique); for a rel_mse budget,
    /// the baseline's time over this one's.
    pub speedup: Option<f64>,
    /// Mean shadow rays per pixel.
    pub shadow_rays_per_pixel: f64,
    /// For rel_mse budgets: whether every repetition reached the target.
    pub reached: bool,
}

/// The rows of one (scene, path length, budget).
#[derive(Clone, Debug, Serialize)]
pub struct Group {
    /// The scene.
    pub scene: String,
    /// Path length.
    pub max_depth: u32,
    /// The budget's name.
    pub budget: String,
    /// One row per technique.
    pub rows: Vec<Row>,
}

/// Whether a run met its relative-MSE target (runs of other budgets always do).
fn reached(r: &RunRecord, suite: &Suite) -> bool {
    suite.budgets[r.spec.budget]
        .rel_mse
        .is_none_or(|target| r.metrics.rel_mse <= target * 1.0001)
}

/// Groups the records by (scene, path length, budget) in suite order.
pub fn aggregate(suite: &Suite, records: &[RunRecord]) -> Vec<Group> {
    let mut groups = Vec::new();
    for s in &suite.scenes {
        for &d in &s.max_depth {
            for (b, budget) in suite.budgets.iter().enumerate() {
                let mut rows: Vec<Row> = Vec::new();
                for (t, tech) in suite.techniques.iter().enumerate() {
                    let runs: Vec<&RunRecord> = records
                        .iter()
                        .filter(|r| {
                            r.spec.scene == s.scene
                                && r.spec.max_depth == d
                                && r.spec.budget == b
                                && r.spec.technique == t
                        })
                        .collect();
                    if runs.is_empty() {
                        continue;
                    }
                    let col = |f: &dyn Fn(&RunRecord) -> f64| {
                        runs.iter().map(|r| f(r)).collect::<Vec<_>>()
                    };
                    let times = col(&|r| r.stats.time_s);
                    let mses = col(&|r| r.metrics.mse);
                    let eff = col(&|r| crate::efficiency(r.metrics.mse, r.stats.time_s));
                    rows.push(Row {
                        technique: tech.label.clone(),
                        runs: runs.len(),
                        spp: Spread::of(&col(&|r| r.stats.spp as f64)).mean,
                        time_s: Spread::of(&times),
                        prepare_s: Spread::of(&col(&|r| r.stats.prepare_s)).mean,
                        mse: Spread::of(&mses),
                        rel_mse: Spread::of(&col(&|r| r.metrics.rel_mse)),
                        efficiency: Spread::of(&eff).mean,
                        speedup: None,
                        shadow_rays_per_pixel: Spread::of(&col(&|r| r.stats.shadow_rays_per_pixel))
                            .mean,
                        reached: runs.iter().all(|r| reached(r, suite)),
                    });
                }
                if let Some(base) = rows
                    .first()
                    .filter(|r| r.technique == suite.techniques[0].label)
                    .cloned()
                {
                    for row in &mut rows {
                        row.speedup = if budget.rel_mse.is_some() {
                            (row.reached && base.reached)
                                .then(|| base.time_s.mean / row.time_s.mean)
                        } else {
                            Some(row.efficiency / base.efficiency)
                        };
                    }
                }
                if !rows.is_empty() {
                    groups.push(Group {
                        scene: s.scene.clone(),
                        max_depth: d,
                        budget: budget.label(),
                        rows,
                    });
                }
            }
        }
    }
    groups
}

fn sci(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.3e}")
    } else {
        "-".into()
    }
}

impl Row {
    /// "mean ± sd" seconds, the preparation's share when there is one, or that the target
    /// was not reached.
    fn time_cell(&self) -> String {
        let prepare = if self.prepare_s >= 0.005 {
            format!(" ({:.2} preparing)", self.prepare_s)
        } else {
            String::new()
        };
        if self.reached {
            format!("{:.2} ± {:.2}{prepare}", self.time_s.mean, self.time_s.sd)
        } else {
            format!("> {:.1} (not reached)", self.time_s.mean)
        }
    }
}

/// The table as Markdown (seed 000 Table 5.1 / seed 004 Tables 4.2-4.3 layout).
pub fn markdown_table(groups: &[Group]) -> String {
    let mut s = String::from("| scene | path length | budget | technique | spp | time s | MSE | relMSE | efficiency | speed-up | shadow rays/px |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    for g in groups {
        for r in &g.rows {
            let speedup = r.speedup.map_or("-".into(), |x| format!("{x:.2}x"));
            let time = r.time_cell();
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.0} | {} | {} ± {} | {} | {} | {} | {:.1} |",
                g.scene,
                g.max_depth,
                g.budget,
                r.technique,
                r.spp,
                time,
                sci(r.mse.mean),
                sci(r.mse.sd),
                sci(r.rel_mse.mean),
                sci(r.efficiency),
                speedup,
                r.shadow_rays_per_pixel
            );
        }
    }
    s
}

/// (spp, time, mse) points of a run's convergence record.
fn convergence(r: &RunRecord) -> Vec<(f64, f64, f64)> {
    r.stats
        .convergence
        .iter()
        .map(|p| (p.spp as f64, p.time_s, p.mse))
        .collect()
}

fn write_text(path: &Path, text: &str) -> Result<(), EvalError> {
    Ok(write_text_atomically(path, text)?)
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Writes results.json, table.md, img/, plots/ and index.html into `out`.
pub fn write_report(
    out: &Path,
    suite: &Suite,
    refs: &[ReferenceRecord],
    records: &[RunRecord],
) -> Result<(), EvalError> {
    let io = |e: std::io::Error| EvalError::File {
        path: out.display().to_string(),
        reason: e.to_string(),
    };
    std::fs::create_dir_all(out.join("img")).map_err(io)?;
    std::fs::create_dir_all(out.join("plots")).map_err(io)?;
    let groups = aggregate(suite, records);
    let results = serde_json::json!({ "suite": suite, "references": refs, "groups": groups, "runs": records });
    write_text(
        &out.join("results.json"),
        &serde_json::to_string_pretty(&results).unwrap_or_default(),
    )?;
    let table = markdown_table(&groups);
    write_text(&out.join("table.md"), &table)?;

    let mut html = String::new();
    let _ = write!(
        html,
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>fenestra bench: {name}</title><style>\
         body{{font-family:sans-serif;margin:2em;max-width:1400px}} table{{border-collapse:collapse;margin:1em 0}}\
         td,th{{border:1px solid #ccc;padding:3px 8px;text-align:right}} th{{background:#eee}}\
         .strip{{display:flex;flex-wrap:wrap;gap:12px}} figure{{margin:0}} figcaption{{font-size:12px;text-align:center}}\
         img.pic{{image-rendering:pixelated;width:256px}} .best{{font-weight:bold}}</style></head><body>\
         <h1>fenestra bench: {name}</h1><p>{desc}</p><p>{w}x{h}, {reps} repetition(s); reference: {ri} at {rs} spp. \
         Efficiency = 1/(MSE x time); speed-up is relative to {base}. Error maps: relative squared error, log scale from 1e-4 (black) to 10 (yellow). \
         Raw data: <a href=\"results.json\">results.json</a>, <a href=\"table.md\">table.md</a>.</p>",
        name = esc(&suite.name),
        desc = esc(&suite.description),
        w = suite.resolution[0],
        h = suite.resolution[1],
        reps = suite.repetitions,
        ri = esc(&suite.reference.integrator),
        rs = suite.reference.spp,
        base = esc(&suite.techniques[0].label),
    );
    // Sections in the suite's order of scenes and path lengths.
    let order = |r: &ReferenceRecord| {
        let s = suite
            .scenes
            .iter()
            .position(|s| s.scene == r.scene)
            .unwrap_or(usize::MAX);
        (s, r.max_depth)
    };
    let mut refs: Vec<&ReferenceRecord> = refs.iter().collect();
    refs.sort_by_key(|r| order(r));
    for reference in refs {
        let ref_img = Image::read(&out.join(&reference.image))?;
        let ev = ref_img.auto_exposure_scale().log2();
        let tag = format!("{}-d{}", slug(&reference.scene), reference.max_depth);
        let (cw, ch) = ((ref_img.width / 4).max(1), (ref_img.height / 4).max(1));
        let (cx, cy) = ((ref_img.width - cw) / 2, (ref_img.height - ch) / 2);
        let zoom = 4;
        let save = |img: &Image, name: &str| -> Result<String, EvalError> {
            let rel = format!("img/{name}.png");
            img.write_png(&out.join(&rel), Some(ev))?;
            Ok(rel)
        };
        let ref_png = save(&ref_img, &format!("{tag}-ref"))?;
        let ref_crop = save(
            &ref_img.crop(cx, cy, cw, ch).upscale(zoom),
            &format!("{tag}-ref-crop"),
        )?;
        let _ = write!(
            html,
            "<h2>{} &mdash; path length {}</h2>",
            esc(&reference.scene),
            reference.max_depth
        );

        // Convergence plots from each technique's longest run (repetition 0).
        let mut by_time = Vec::new();
        let mut by_spp = Vec::new();
        for (t, tech) in suite.techniques.iter().enumerate() {
            let longest = records
                .iter()
                .filter(|r| {
                    r.spec.scene == reference.scene
                        && r.spec.max_depth == reference.max_depth
                        && r.spec.technique == t
                        && r.spec.repetition == 0
                })
                .max_by(|a, b| a.stats.time_s.total_cmp(&b.stats.time_s));
            if let Some(r) = longest {
                let c = convergence(r);
                by_time.push(Series {
                    label: tech.label.clone(),
                    points: c.iter().map(|&(_, t, m)| (t, m)).collect(),
                });
                by_spp.push(Series {
                    label: tech.label.clone(),
                    points: c.iter().map(|&(s, _, m)| (s, m)).collect(),
                });
            }
        }
        let title = format!("{} path length {}", reference.scene, reference.max_depth);
        loglog(
            &out.join(format!("plots/{tag}-time.svg")),
            &title,
            "time (s)",
            "MSE",
            &by_time,
        )?;
        loglog(
            &out.join(format!("plots/{tag}-spp.svg")),
            &title,
            "samples per pixel",
            "MSE",
            &by_spp,
        )?;
        let _ = write!(html, "<div class=\"strip\"><img src=\"plots/{tag}-time.svg\" width=\"560\"><img src=\"plots/{tag}-spp.svg\" width=\"560\"></div>");

        for g in groups
            .iter()
            .filter(|g| g.scene == reference.scene && g.max_depth == reference.max_depth)
        {
            let _ = write!(
                html,
                "<h3>budget {}</h3><table><tr><th>technique</th><th>spp</th><th>time s</th><th>MSE</th><th>relMSE</th><th>efficiency</th><th>speed-up</th><th>shadow rays/px</th></tr>",
                esc(&g.budget)
            );
            let best = g.rows.iter().map(|r| r.efficiency).fold(f64::MIN, f64::max);
            for r in &g.rows {
                let class = if r.efficiency == best {
                    " class=\"best\""
                } else {
                    ""
                };
                let time = esc(&r.time_cell());
                let _ = write!(
                    html,
                    "<tr{class}><td>{}</td><td>{:.0}</td><td>{time}</td><td>{} ± {}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.1}</td></tr>",
                    esc(&r.technique),
                    r.spp,
                    sci(r.mse.mean),
                    sci(r.mse.sd),
                    sci(r.rel_mse.mean),
                    sci(r.efficiency),
                    r.speedup.map_or("-".into(), |x| format!("{x:.2}x")),
                    r.shadow_rays_per_pixel
                );
            }
            html.push_str("</table><div class=\"strip\">");
            let _ = write!(html, "<figure><img class=\"pic\" src=\"{ref_png}\"><img class=\"pic\" src=\"{ref_crop}\"><figcaption>reference</figcaption></figure>");
            for r in records.iter().filter(|r| {
                r.spec.scene == g.scene
                    && r.spec.max_depth == g.max_depth
                    && suite.budgets[r.spec.budget].label() == g.budget
                    && r.spec.repetition == 0
            }) {
                let img = Image::read(&out.join(&r.image))?;
                let png = save(&img, &r.spec.id)?;
                let crop = save(
                    &img.crop(cx, cy, cw, ch).upscale(zoom),
                    &format!("{}-crop", r.spec.id),
                )?;
                let err = format!("img/{}-err.png", r.spec.id);
                write_error_map(&img, &ref_img, &out.join(&err))?;
                let _ = write!(
                    html,
                    "<figure><img class=\"pic\" src=\"{png}\"><img class=\"pic\" src=\"{crop}\"><img class=\"pic\" src=\"{err}\"><figcaption>{} (MSE {})</figcaption></figure>",
                    esc(&suite.techniques[r.spec.technique].label),
                    sci(r.metrics.mse)
                );
            }
            html.push_str("</div>");
        }
    }
    html.push_str("</body></html>\n");
    write_text(&out.join("index.html"), &html)
}
