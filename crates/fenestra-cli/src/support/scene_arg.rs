//! Turning the SCENE argument into a scene description: `builtin:NAME`, a pbrt-v4 file, or an
//! OBJ/PLY mesh staged for viewing.

use anyhow::{bail, Result};
use fenestra_builtin as builtin;
use fenestra_pbrt as pbrt;
use fenestra_scene::{mesh, SceneDesc};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// How scene files are read.
#[derive(clap::Args, Clone, Copy, Debug, Default)]
pub struct SceneOptions {
    /// Refuse scene files that use anything fenestra does not support (instead of warning).
    #[arg(long)]
    pub strict: bool,
}

/// A loaded scene with its load time, what it could not represent and the files it read.
pub struct LoadedScene {
    pub desc: SceneDesc,
    /// What a pbrt-v4 file asks for that fenestra replaces by something else.
    pub substitutions: Vec<pbrt::Warning>,
    /// What a pbrt-v4 file asks for that fenestra renders in its own documented way.
    pub notes: Vec<pbrt::Warning>,
    /// Other warnings: mesh files, a scene without light.
    pub other: Vec<String>,
    pub seconds: f64,
    /// Every file read (scene, includes, meshes, images): outputs must not replace them.
    pub files: Vec<PathBuf>,
}

impl LoadedScene {
    /// Every warning as a line of text: substitutions, then the others.
    pub fn warnings(&self) -> Vec<String> {
        let subs = self.substitutions.iter().map(ToString::to_string);
        subs.chain(self.other.iter().cloned()).collect()
    }
}

/// Loads `arg`, printing warnings about unsupported input to stderr.
pub fn load(arg: &str, opts: SceneOptions) -> Result<LoadedScene> {
    let loaded = load_quietly(arg, opts)?;
    for w in loaded.warnings() {
        eprintln!("warning: {w}");
    }
    Ok(loaded)
}

pub fn load_quietly(arg: &str, opts: SceneOptions) -> Result<LoadedScene> {
    let start = Instant::now();
    let (mut substitutions, mut notes) = (Vec::new(), Vec::new());
    let (desc, warnings, files) = if let Some(name) = arg.strip_prefix("builtin:") {
        (builtin::load(name)?, Vec::new(), Vec::new())
    } else {
        let path = Path::new(arg);
        match mesh::format_of(path).as_deref() {
            Some("pbrt") => {
                let l = pbrt::load(path, opts.strict)?;
                (substitutions, notes) = (l.warnings, l.notes);
                (l.desc, Vec::new(), l.files)
            }
            Some("obj" | "ply") => {
                let (desc, warnings) = mesh::viewer_scene(path)?;
                let textures = desc
                    .materials
                    .iter()
                    .filter_map(|m| m.texture().map(|t| t.path.clone()));
                let files = std::iter::once(path.to_path_buf()).chain(textures).collect();
                (desc, warnings, files)
            }
            _ => bail!(
                "{arg}: unknown scene type (expected a .pbrt or .pbrt.gz file, an .obj or .ply mesh, or builtin:NAME; `fenestra list` shows the built-in scenes)"
            ),
        }
    };
    let mut warnings = warnings;
    if desc.lights.is_empty() && desc.shapes.iter().all(|s| s.emission.is_none()) {
        warnings.push(format!(
            "{arg}: the scene has no light (no light source, no emissive shape): it renders black"
        ));
    }
    Ok(LoadedScene {
        desc,
        substitutions,
        notes,
        other: warnings,
        seconds: start.elapsed().as_secs_f64(),
        files,
    })
}
