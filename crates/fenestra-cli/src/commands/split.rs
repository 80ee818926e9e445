//! `fenestra split`: a render cut into parts (sample ranges or tiles) written as a ready job
//! for a distributed engine ([`crate::support::job`]): a step whose tasks render the parts, and a step
//! after it that merges them.

use crate::commands::render::{shape, RenderShape};
use crate::support::engine_job::{Engine, EngineJob, Step, PART, PIECE};
use crate::support::pieces;
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use fenestra_render::integrator::Split;
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum By {
    /// Every part renders the whole image with its own range of samples.
    Samples,
    /// Every part renders a band of rows with all the samples (ias splits only this way).
    Tiles,
}

#[derive(Args)]
pub struct SplitArgs {
    /// How many parts.
    #[arg(long)]
    parts: u32,
    /// How to cut the render.
    #[arg(long, value_enum, default_value = "samples")]
    by: By,
    /// The engine that runs the job.
    #[arg(long, value_enum)]
    engine: Engine,
    /// Job folder: the job's files, the parts (parts/), logs (logs/) and the merged image
    /// (merged.exr). Every machine must see it at this path.
    #[arg(short, long)]
    output: PathBuf,
    /// The fenestra executable the job runs, as every machine sees it (default: this one).
    #[arg(long)]
    fenestra: Option<PathBuf>,
    /// The scene, then the options of `fenestra render` (without -o, --time, --samples or
    /// --crop), e.g. `builtin:box-hole --spp 1024 --resolution 1024x1024`.
    #[arg(
        required = true,
        num_args = 1..,
        trailing_var_arg = true,
        allow_hyphen_values = true,
        value_name = "SCENE [RENDER OPTIONS]"
    )]
    render: Vec<String>,
}

pub fn run(args: SplitArgs) -> Result<()> {
    let shape = shape(&args.render)?;
    let job = plan(&args, &shape)?;
    let parts = job.dir.join("parts");
    std::fs::create_dir_all(&parts)
        .with_context(|| format!("cannot create {}", parts.display()))?;
    let written = job.write(args.engine)?;
    println!(
        "{}: {} parts by {} in {}; the merged image will be {}",
        job.title,
        job.steps[0].pieces.len(),
        match args.by {
            By::Samples => "sample ranges",
            By::Tiles => "tiles",
        },
        job.dir.display(),
        job.dir.join("merged.exr").display()
    );
    for (path, how) in written {
        println!("wrote {} ({how})", path.display());
    }
    Ok(())
}

/// The job: a step "Render" with a task per part (parts/part-K.exr and .film) and a step
/// "Merge" (merged.exr).
fn plan(args: &SplitArgs, shape: &RenderShape) -> Result<EngineJob> {
    let dir = std::path::absolute(&args.output)
        .with_context(|| format!("cannot place {}", args.output.display()))?;
    let fenestra = match &args.fenestra {
        Some(p) => p.clone(),
        None => std::env::current_exe().context("cannot find the fenestra executable")?,
    };
    if shape.split == Split::Whole {
        bail!(
            "{} learns from, or builds caches from, every pixel's samples: it cannot be split",
            shape.integrator
        );
    }
    let (flag, pieces, total): (_, Vec<String>, _) = match args.by {
        By::Samples if shape.split == Split::BlockTiles => bail!(
            "{} decides its own samples per pixel: split it with --by tiles",
            shape.integrator
        ),
        By::Samples => (
            "--samples",
            pieces::by_samples(shape.spp, args.parts)?
                .iter()
                .map(ToString::to_string)
                .collect(),
            Some(shape.spp),
        ),
        By::Tiles if shape.split == Split::Samples => bail!(
            "{}'s light paths bring light to every part of the image: split it with --by samples",
            shape.integrator
        ),
        By::Tiles => (
            "--crop",
            pieces::by_tiles(shape.width, shape.height, args.parts)?
                .iter()
                .map(ToString::to_string)
                .collect(),
            (shape.split == Split::SamplesOrTiles).then_some(shape.spp),
        ),
    };
    let part = |i: &str| dir.join(format!("parts/part-{i}")).display().to_string();
    let mut render = part_args(&args.render, args.by == By::Samples)?;
    render.extend([flag.into(), PIECE.into(), "-o".into(), part(PART) + ".exr"]);
    let mut merge = vec!["merge".to_string()];
    merge.extend((0..pieces.len()).map(|i| part(&i.to_string()) + ".film"));
    if let Some(n) = total {
        merge.extend(["--total".into(), n.to_string()]);
    }
    merge.extend(["-o".into(), dir.join("merged.exr").display().to_string()]);
    Ok(EngineJob {
        title: format!(
            "{} at {}x{}, {} spp",
            shape.scene, shape.width, shape.height, shape.spp
        ),
        fenestra: fenestra.display().to_string(),
        dir,
        steps: vec![
            Step {
                name: "Render",
                args: render,
                pieces,
                whole_machine: true,
            },
            Step {
                name: "Merge",
                args: merge,
                pieces: Vec::new(),
                whole_machine: false,
            },
        ],
    })
}

/// `render` followed by the user's arguments as every machine must see them: the scene file
/// and a --portals file absolute, and --spp dropped when parts take sample ranges (theirs
/// say how many).
fn part_args(user: &[String], drop_spp: bool) -> Result<Vec<String>> {
    let absolute = |p: &str| -> Result<String> {
        Ok(std::path::absolute(Path::new(p))
            .with_context(|| format!("cannot place {p}"))?
            .display()
            .to_string())
    };
    let mut out = vec!["render".to_string()];
    let mut it = user.iter().peekable();
    let scene = it.next().expect("clap requires the scene");
    out.push(if scene.starts_with("builtin:") {
        scene.clone()
    } else {
        absolute(scene)?
    });
    while let Some(a) = it.next() {
        match a.as_str() {
            "--spp" if drop_spp => {
                it.next();
            }
            s if drop_spp && s.starts_with("--spp=") => {}
            "--portals" => {
                out.push(a.clone());
                if let Some(v) = it.next() {
                    out.push(if v == "auto" { v.clone() } else { absolute(v)? });
                }
            }
            _ => out.push(a.clone()),
        }
    }
    out.push("--quiet".into());
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_drop_spp_and_place_files() {
        let args: Vec<String> = [
            "scene.pbrt",
            "--spp",
            "64",
            "--portals",
            "p.json",
            "--spp=3",
        ]
        .map(String::from)
        .to_vec();
        let out = part_args(&args, true).expect("args");
        assert_eq!(out[0], "render");
        assert!(Path::new(&out[1]).is_absolute() && out[1].ends_with("scene.pbrt"));
        assert_eq!(out[2], "--portals");
        assert!(Path::new(&out[3]).is_absolute());
        assert_eq!(out[4..], ["--quiet"]);
        let kept = part_args(&args, false).expect("args");
        assert!(kept.contains(&"--spp".to_string()) && kept.contains(&"--spp=3".to_string()));
    }

    /// Each integrator's way of splitting is kept: adaptive ones by tiles, light paths by
    /// samples, caches not at all.
    #[test]
    fn integrators_split_only_as_they_can() {
        let plan_of = |split: Split, by: By| {
            let args = SplitArgs {
                parts: 2,
                by,
                engine: Engine::Slurm,
                output: std::env::temp_dir().join("fenestra-split-plan"),
                fenestra: Some(PathBuf::from("/bin/fenestra")),
                render: vec!["builtin:box-hole".into()],
            };
            let shape = RenderShape {
                scene: "box-hole".into(),
                integrator: "x".into(),
                spp: 8,
                width: 32,
                height: 16,
                split,
            };
            plan(&args, &shape).map(|_| ()).map_err(|e| e.to_string())
        };
        for by in [By::Samples, By::Tiles] {
            assert!(plan_of(Split::SamplesOrTiles, by).is_ok());
            let e = plan_of(Split::Whole, by).expect_err("whole");
            assert!(e.contains("cannot be split"), "{e}");
        }
        assert!(plan_of(Split::BlockTiles, By::Tiles).is_ok());
        let e = plan_of(Split::BlockTiles, By::Samples).expect_err("blocks");
        assert!(e.contains("split it with --by tiles"), "{e}");
        assert!(plan_of(Split::Samples, By::Samples).is_ok());
        let e = plan_of(Split::Samples, By::Tiles).expect_err("light paths");
        assert!(e.contains("split it with --by samples"), "{e}");
    }
}
