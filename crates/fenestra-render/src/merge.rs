//! Merging the pieces of a render split across machines: film-state files of sample ranges
//! and of tiles ([`crate::film_file`]) checked to belong together, to overlap nowhere and to
//! leave nothing out, then summed. The film's sums are exact integers, so the merge is the
//! film one render of the union would have made, whatever the split and the order.

use crate::film::{Film, Window};
use crate::film_file::{self, FilmFileError, FilmHeader, SampleRange};
use fenestra_core::stats::RenderStats;
use std::path::{Path, PathBuf};

/// Why parts do not merge.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    /// A part could not be read.
    #[error(transparent)]
    File(#[from] FilmFileError),
    /// The parts do not make one render.
    #[error("{0}")]
    Parts(String),
}

/// One part: its file and header.
#[derive(Clone, Debug)]
pub struct Part {
    /// The film-state file.
    pub path: PathBuf,
    /// Its header.
    pub header: FilmHeader,
}

impl Part {
    /// Reads the header of the part at `path`.
    pub fn open(path: &Path) -> Result<Part, MergeError> {
        Ok(Part {
            path: path.to_path_buf(),
            header: film_file::read_header(path)?,
        })
    }

    fn name(&self) -> String {
        self.path.display().to_string()
    }
}

/// What the parts make together.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Plan {
    /// The part of the image they cover.
    pub window: Window,
    /// The samples every pixel of it has (none for adaptive integrators).
    pub samples: Option<SampleRange>,
}

/// Checks that `parts` are pieces of one render (same scene, settings and image, none
/// interrupted), that no two hold the same sample of a pixel and that together they cover a
/// rectangle of the image with the same contiguous sample range everywhere (with `total`:
/// samples 0..total); says which part or piece is wrong or missing.
pub fn plan(parts: &[Part], total: Option<u32>) -> Result<Plan, MergeError> {
    let fail = |text: String| Err(MergeError::Parts(text));
    let Some(first) = parts.first() else {
        return fail("no parts to merge".into());
    };
    for part in parts {
        if let Some(why) = mismatch(&first.header, &part.header) {
            // A damaged header differs too: say so rather than what it seems to say.
            for p in [first, part] {
                film_file::verify(&p.path)?;
            }
            return fail(format!(
                "{} and {} are not parts of one render: {why}",
                first.name(),
                part.name()
            ));
        }
        if part.header.stats.interrupted {
            return fail(format!(
                "{} was interrupted before it finished its samples: render it again",
                part.name()
            ));
        }
    }
    let windows: Vec<Window> = parts.iter().map(|p| p.header.window).collect();
    let cut = |f: fn(&Window) -> [u32; 2]| {
        let mut v: Vec<u32> = windows.iter().flat_map(f).collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    let (xs, ys) = (cut(|w| [w.x0, w.x1]), cut(|w| [w.y0, w.y1]));
    let bounds = Window {
        x0: xs[0],
        y0: ys[0],
        x1: xs[xs.len() - 1],
        y1: ys[ys.len() - 1],
        ..first.header.window
    };
    let mut whole: Option<Option<SampleRange>> = None;
    for y in ys.windows(2) {
        for x in xs.windows(2) {
            let cell = Window {
                x0: x[0],
                x1: x[1],
                y0: y[0],
                y1: y[1],
                ..bounds
            };
            let mut here: Vec<&Part> = parts
                .iter()
                .filter(|p| p.header.window.overlaps(&cell))
                .collect();
            let covered = cell_samples(&mut here, &cell)?;
            match whole {
                None => whole = Some(covered),
                Some(w) if w == covered => {}
                Some(w) => {
                    return fail(format!(
                        "pixels {cell} have {} where the others have {}",
                        describe(covered),
                        describe(w)
                    ))
                }
            }
        }
    }
    let samples = whole.flatten();
    if let (Some(total), Some(s)) = (total, samples) {
        if s.start != 0 || s.end != total {
            let mut missing = Vec::new();
            if s.start > 0 {
                missing.push(format!("0..{}", s.start));
            }
            if s.end < total {
                missing.push(format!("{}..{total}", s.end));
            }
            if s.end > total {
                return fail(format!(
                    "the parts hold samples {s}, beyond --total {total}"
                ));
            }
            return fail(format!(
                "samples {} are missing (the parts hold {s} of 0..{total})",
                missing.join(" and ")
            ));
        }
    }
    Ok(Plan {
        window: bounds,
        samples,
    })
}

fn describe(samples: Option<SampleRange>) -> String {
    samples.map_or("an adaptive render".into(), |s| format!("samples {s}"))
}

/// The samples the parts covering `cell` give it: one part of an adaptive render, or sample
/// ranges that do not overlap and leave no gap.
fn cell_samples(here: &mut [&Part], cell: &Window) -> Result<Option<SampleRange>, MergeError> {
    let fail = |text: String| Err(MergeError::Parts(text));
    here.sort_by_key(|p| p.header.samples.map(|s| s.start));
    let Some(first) = here.first() else {
        return fail(format!("pixels {cell} are in no part"));
    };
    if first.header.samples.is_none() {
        if let [a, b, ..] = here {
            return fail(format!(
                "{} and {} overlap: both hold pixels {cell}",
                a.name(),
                b.name()
            ));
        }
        return Ok(None);
    }
    let range = |p: &Part| p.header.samples.expect("all parts have sample ranges");
    let mut union = range(first);
    for pair in here.windows(2) {
        let (a, b) = (range(pair[0]), range(pair[1]));
        if b.start < a.end {
            return fail(format!(
                "{} and {} overlap: both hold samples {}..{} of pixels {cell}",
                pair[0].name(),
                pair[1].name(),
                b.start,
                a.end.min(b.end)
            ));
        }
        if b.start > a.end {
            return fail(format!(
                "samples {}..{} of pixels {cell} are missing (between {} and {})",
                a.end,
                b.start,
                pair[0].name(),
                pair[1].name()
            ));
        }
        union.end = b.end;
    }
    Ok(Some(union))
}

fn area(w: &Window) -> f64 {
    f64::from(w.width()) * f64::from(w.height())
}

/// What makes two parts' renders differ, if anything.
fn mismatch(a: &FilmHeader, b: &FilmHeader) -> Option<String> {
    let (s, t) = (&a.stats, &b.stats);
    let differ = |what: &str, x: String, y: String| Some(format!("{what} {x} vs {y}"));
    if s.scene != t.scene {
        return differ("scene", s.scene.clone(), t.scene.clone());
    }
    if s.integrator != t.integrator {
        return differ("integrator", s.integrator.clone(), t.integrator.clone());
    }
    if s.settings != t.settings {
        return differ("settings", s.settings.to_string(), t.settings.to_string());
    }
    if s.seed != t.seed {
        return differ("seed", s.seed.to_string(), t.seed.to_string());
    }
    let (v, w) = (a.window, b.window);
    if (v.full_width, v.full_height) != (w.full_width, w.full_height) {
        return differ(
            "resolution",
            format!("{}x{}", v.full_width, v.full_height),
            format!("{}x{}", w.full_width, w.full_height),
        );
    }
    if s.backend != t.backend {
        return differ("ray backend", s.backend.clone(), t.backend.clone());
    }
    if a.features != b.features {
        return Some(
            "one holds denoising features, the other not (every part takes them or none does)"
                .into(),
        );
    }
    if a.samples.is_some() != b.samples.is_some() {
        return Some("one is split by samples, the other adaptive".into());
    }
    (a.key != b.key).then(|| {
        format!(
            "the scene's content or fenestra's version differs (keys {} vs {})",
            a.key, b.key
        )
    })
}

/// Merges the parts by `plan` (from [`plan`]): the film of their union and statistics that
/// add their rays and their times (seconds of all machines together); the integrator's own
/// per-pixel figures (`extra`) are averaged over the parts, weighted by their pixels, but for
/// the light paths, which are counted.
pub fn merge(parts: &[Part], plan: &Plan) -> Result<(Film, RenderStats), MergeError> {
    let Some(first) = parts.first() else {
        return Err(MergeError::Parts("no parts to merge".into()));
    };
    let mut film = Film::cropped(plan.window);
    if first.header.features {
        film = film.with_features();
    }
    let mut stats = first.header.stats.clone();
    stats.rays = Default::default();
    stats.time_s = 0.0;
    stats.prepare_s = 0.0;
    stats.passes = 0;
    stats.convergence.clear();
    stats.extra.clear();
    let pixels: f64 = parts.iter().map(|p| area(&p.header.window)).sum();
    for part in parts {
        let header = film_file::add_into(&part.path, &mut film)?;
        if header != part.header {
            return Err(MergeError::Parts(format!(
                "{} changed while it was being merged",
                part.name()
            )));
        }
        let s = &header.stats;
        stats.rays += s.rays;
        stats.time_s += s.time_s;
        stats.prepare_s += s.prepare_s;
        stats.passes = stats.passes.max(s.passes);
        let share = area(&header.window) / pixels;
        for (name, value) in &s.extra {
            *stats.extra.entry(name.clone()).or_default() += value * share;
        }
    }
    // Light paths add up over sample ranges rather than average over pixels.
    if film.light_paths > 0 {
        let extra = &mut stats.extra;
        extra.insert("light_paths".into(), film.light_paths as f64);
        match film.light_path_share() {
            Some(share) => extra.insert("light_path_share".into(), share),
            None => extra.remove("light_path_share"),
        };
    }
    (stats.spp, stats.spp_max) = film.sample_count_range();
    (stats.width, stats.height) = (film.width, film.height);
    stats.extra.insert("parts".into(), parts.len() as f64);
    stats.derive_rates();
    Ok((film, stats))
}
