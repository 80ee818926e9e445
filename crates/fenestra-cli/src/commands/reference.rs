//! `fenestra reference`: a high-sample render kept in a cache folder under a key of
//! everything that changes the picture (docs/measuring.md), rendered again only when missing
//! or unusable.

use super::render::RenderOpts;
use anyhow::{bail, Context, Result};
use clap::Args;
use fenestra_core::image::Image;
use fenestra_eval::run::{ReferenceSummary, REFERENCE_SEED_OFFSET};
use fenestra_render::output::{self, Extras};
use fenestra_render::RenderStats;
use fenestra_session::files::{check_exr, render_outputs, Beside};
use fenestra_session::Rendered;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct ReferenceArgs {
    /// Folder of cached references, keyed by scene content, settings and resolution.
    #[arg(long, default_value = "refs")]
    cache: PathBuf,
    #[command(flatten)]
    opts: RenderOpts,
}

/// Checks a cached reference before serving it: its sidecar names `key` and a finished
/// render, and its image and variance image read back at the render's size.
fn verify_reference(path: &Path, key: &str, width: u32, height: u32) -> Result<()> {
    let sidecar = output::companion_paths(path).1;
    let text = std::fs::read_to_string(&sidecar)
        .with_context(|| format!("cannot read {}", sidecar.display()))?;
    let stats: RenderStats = serde_json::from_str(&text)
        .with_context(|| format!("{} is not a render's sidecar", sidecar.display()))?;
    if stats.reference_key.as_deref() != Some(key) || stats.interrupted {
        bail!("its sidecar is not that of this reference");
    }
    for image in [path.to_path_buf(), output::variance_path(path)] {
        let img = Image::read(&image)?;
        if (img.width, img.height) != (width as usize, height as usize) {
            bail!("{} is {}x{}", image.display(), img.width, img.height);
        }
    }
    Ok(())
}

/// Renders a reference into the cache, or finds it there; prints where it is.
pub fn run(args: ReferenceArgs) -> Result<()> {
    let mut job = args.opts.job(None, false)?;
    job.settings.seed = job.settings.seed.wrapping_add(REFERENCE_SEED_OFFSET);
    let key = job.key(args.opts.bvh.unwrap_or_default());
    let path = args.cache.join(format!(
        "{}-{key:016x}.exr",
        fenestra_core::fs::slug(&job.desc().name)
    ));
    let sidecar = output::companion_paths(&path).1;
    let mut summary = ReferenceSummary {
        path: path.clone(),
        cached: true,
        sidecar: sidecar.clone(),
        key: format!("{key:016x}"),
    };
    let (width, height) = job.size();
    let cached = match verify_reference(&path, &format!("{key:016x}"), width, height) {
        Ok(()) => true,
        Err(why) => {
            if path.exists() && !args.opts.quiet {
                eprintln!(
                    "cached reference {} is unusable ({why}): rendering it again",
                    path.display()
                );
            }
            false
        }
    };
    if !cached {
        check_exr(&path)?;
        let mut files = std::mem::take(&mut job.inputs);
        let beside = Beside {
            variance: true,
            ..Beside::default()
        };
        render_outputs(&mut files, &path, beside).check()?;
        let Rendered {
            mut stats, film, ..
        } = args.opts.run(job, None, None)?;
        if stats.interrupted {
            bail!("reference interrupted: nothing cached");
        }
        stats.reference_key = Some(format!("{key:016x}"));
        let extras = Extras {
            exposure: args.opts.exposure,
            variance: true,
            ..Extras::default()
        };
        output::write_render(&path, &film, &stats, &extras)?;
        if !args.opts.json {
            println!("{}", stats.summary());
        }
        summary.cached = false;
    }
    if args.opts.json {
        println!("{}", serde_json::to_string(&summary)?);
    } else {
        let how = if summary.cached { "cached" } else { "rendered" };
        println!("reference {} ({how})", path.display());
    }
    Ok(())
}
