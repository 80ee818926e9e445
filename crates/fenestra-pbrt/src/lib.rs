//! The pbrt-v4 scene format: a lexer and parser for the whole syntax and a builder that maps
//! the supported subset onto fenestra's scene model. What the builder cannot represent is
//! reported once per kind with its count and first location (an error with `strict`).
//! docs/scenes.md lists what is supported and how each approximation is made.

mod builder;
mod camera;
mod equal_area;
pub mod export;
mod lexer;
mod lights;
mod materials;
mod params;
mod parser;
mod rendering;
mod shapes;
mod spectra;
mod textures;

use fenestra_scene::SceneDesc;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A position in a scene file (1-based line and column, in characters).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Loc {
    /// The file.
    pub file: Arc<PathBuf>,
    /// Line, from 1.
    pub line: u32,
    /// Column, from 1.
    pub col: u32,
}

impl fmt::Display for Loc {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.col)
    }
}

/// A scene file that cannot be read, and where.
#[derive(Debug, thiserror::Error)]
#[error("{loc}: {msg}")]
pub struct PbrtError {
    /// Where in which file.
    pub loc: Loc,
    /// What was expected or is wrong.
    pub msg: String,
}

impl PbrtError {
    /// The error `msg` at `loc`.
    pub fn at(loc: &Loc, msg: impl std::fmt::Display) -> Self {
        PbrtError {
            loc: loc.clone(),
            msg: msg.to_string(),
        }
    }
}

/// What part of a scene a warning is about, for grouping.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Topic {
    /// Shapes and meshes.
    Geometry,
    /// Materials.
    Materials,
    /// Textures.
    Textures,
    /// Light sources.
    Lights,
    /// Camera, film and pixel filter.
    Camera,
    /// Integrator, media, colour spaces and options.
    Rendering,
}

impl Topic {
    /// The topic of a directive's own parameters.
    pub(crate) fn of_directive(name: &str) -> Topic {
        match name {
            "Shape" | "ObjectBegin" | "ObjectInstance" => Topic::Geometry,
            "Material" | "MakeNamedMaterial" => Topic::Materials,
            "Texture" => Topic::Textures,
            "LightSource" | "AreaLightSource" => Topic::Lights,
            "Camera" | "Film" | "PixelFilter" | "Sampler" => Topic::Camera,
            _ => Topic::Rendering,
        }
    }
}

impl fmt::Display for Topic {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(match self {
            Topic::Geometry => "geometry",
            Topic::Materials => "materials",
            Topic::Textures => "textures",
            Topic::Lights => "lights",
            Topic::Camera => "camera and film",
            Topic::Rendering => "rendering",
        })
    }
}

/// Something the file asks for that fenestra does not do, or does in its own way, counted
/// over the whole scene.
#[derive(Clone, Debug)]
pub struct Warning {
    /// What part of the scene it concerns.
    pub topic: Topic,
    /// What is not supported and what stands in for it.
    pub what: String,
    /// How many times the scene asks for it.
    pub count: usize,
    /// Where it first does.
    pub first: Loc,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{}: unsupported: {}", self.first, self.what)?;
        if self.count > 1 {
            write!(f, " ({} times)", self.count)?;
        }
        Ok(())
    }
}

/// A scene read from a file, with what could not be represented.
pub struct Loaded {
    /// The scene.
    pub desc: SceneDesc,
    /// What it asks for that fenestra does not do, and what stands in for it (refused in
    /// strict mode).
    pub warnings: Vec<Warning>,
    /// What fenestra renders in its own documented way (docs/scenes.md), such as analytic
    /// layered materials where pbrt-v4 simulates the layers: the picture differs a little.
    pub notes: Vec<Warning>,
    /// Every file read: the scene file, what it includes, PLY meshes and images.
    pub files: Vec<PathBuf>,
}

/// Reads a pbrt-v4 scene file (and what it includes). With `strict`, anything unsupported is
/// an error instead of a warning.
pub fn load(path: &Path, strict: bool) -> Result<Loaded, PbrtError> {
    let start = Loc {
        file: Arc::new(path.to_path_buf()),
        line: 1,
        col: 1,
    };
    let bytes = fenestra_scene::compressed::read(path)
        .map_err(|e| PbrtError::at(&start, format!("cannot read scene file: {e}")))?;
    load_bytes(&bytes, path, strict)
}

/// Reads a scene from memory; `path` names it in messages and anchors relative includes.
pub fn load_bytes(bytes: &[u8], path: &Path, strict: bool) -> Result<Loaded, PbrtError> {
    let mut b = builder::Builder::new();
    b.run_bytes(bytes, path, None)?;
    let name = path
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    let mut files = vec![path.to_path_buf()];
    files.append(&mut b.files);
    let (desc, warnings, notes) = b.finish(name)?;
    if strict && !warnings.is_empty() {
        let w = &warnings[0];
        let more = match warnings.len() {
            1 => String::new(),
            n => format!(" (and {} more kinds of unsupported input)", n - 1),
        };
        return Err(PbrtError::at(
            &w.first,
            format!("unsupported in strict mode: {}{more}", w.what),
        ));
    }
    Ok(Loaded {
        desc,
        warnings,
        notes,
        files,
    })
}
