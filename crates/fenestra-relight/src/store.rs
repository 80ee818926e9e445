//! A precomputed sequence on disk, a folder:
//!
//! ```text
//! relight.json      the manifest: scene, size, frames, every precomputation setting
//! animation.json    the animation it was precomputed for (a copy)
//! lights.json       the scene's own lights, as a starting point for relighting
//! frames/NNNN.rlf   one file per frame (frame_file), written atomically when it is done
//! ```
//!
//! A precomputation interrupted keeps its finished frames; run again with the same settings
//! it computes only the missing ones. Other settings in the same folder are refused.

use crate::error::RelightError;
use crate::frame::FrameOptions;
use crate::frame_file;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

const VERSION: u32 = 1;

/// What a precomputation is, all of it that changes its frames.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    pub version: u32,
    /// The scene as given to `precompute` (`builtin:NAME` or an absolute path).
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub frames: u32,
    /// Gather samples.
    pub gather: usize,
    pub threshold: f32,
    /// Monte Carlo rays per transfer vector (0: the N-body traversal).
    #[serde(default)]
    pub mc_rays: u32,
    /// Points a gather sample's patch area is measured with (0: frames made when every
    /// sample had an equal share of the area).
    #[serde(default)]
    pub patch_points: usize,
    pub explored: f32,
    pub batches: usize,
    pub keep: usize,
    pub clusters: usize,
    pub schedule: String,
    pub neighbours: usize,
    pub elements: usize,
    pub ridge: f64,
    /// Share of view samples evaluated after reconstruction and kept uncompressed (0: frames
    /// made before this existed).
    #[serde(default)]
    pub refined: f32,
    pub seed: u64,
}

impl Manifest {
    /// The manifest of `scene` at `width` x `height`, `frames` frames, with `o`.
    pub fn new(
        scene: &str,
        width: u32,
        height: u32,
        frames: u32,
        gather: usize,
        o: &FrameOptions,
    ) -> Self {
        Manifest {
            version: VERSION,
            scene: scene.to_string(),
            width,
            height,
            frames,
            gather,
            threshold: o.threshold,
            mc_rays: o.mc_rays,
            patch_points: crate::gather::PATCH_POINTS,
            explored: o.explored,
            batches: o.batches,
            keep: o.keep,
            clusters: o.clusters,
            schedule: o.schedule.to_string(),
            neighbours: o.neighbours,
            elements: o.elements,
            ridge: o.ridge,
            refined: o.refined,
            seed: o.seed,
        }
    }
}

/// A precomputation folder.
#[derive(Clone, Debug)]
pub struct Store {
    pub dir: PathBuf,
    pub manifest: Manifest,
}

impl Store {
    /// Starts a precomputation in `dir` (made if missing), or resumes the one there if its
    /// manifest is `manifest`; writes the manifest, `animation` (its JSON) and `lights`.
    pub fn create_or_resume(
        dir: &Path,
        manifest: Manifest,
        animation: &str,
        lights: &str,
    ) -> Result<Self, RelightError> {
        Self::created(dir, manifest, animation, lights)
    }

    fn created(
        dir: &Path,
        manifest: Manifest,
        animation: &str,
        lights: &str,
    ) -> Result<Self, RelightError> {
        let at = |e: &dyn std::fmt::Display, p: &Path| {
            RelightError::Store(format!("{}: {e}", p.display()))
        };
        std::fs::create_dir_all(dir.join("frames")).map_err(|e| at(&e, dir))?;
        let path = dir.join("relight.json");
        if path.exists() {
            let old = Self::open(dir)?;
            if old.manifest != manifest {
                let (a, b) = (
                    serde_json::to_value(&old.manifest),
                    serde_json::to_value(&manifest),
                );
                let differs = match (a, b) {
                    (Ok(serde_json::Value::Object(a)), Ok(serde_json::Value::Object(b))) => (a
                        .iter())
                    .filter(|(k, v)| b.get(*k) != Some(v))
                    .map(|(k, v)| {
                        format!(
                            "{k} {v} there, {} now",
                            b.get(k).map_or("none".into(), |x| x.to_string())
                        )
                    })
                    .collect::<Vec<_>>()
                    .join("; "),
                    _ => String::new(),
                };
                return Err(RelightError::Store(format!(
                    "{} holds a precomputation with other settings ({differs}): use another folder or remove it",
                    dir.display()
                )));
            }
        }
        let json = serde_json::to_string_pretty(&manifest).map_err(|e| at(&e, dir))?;
        for (name, text) in [
            ("relight.json", json.as_str()),
            ("animation.json", animation),
            ("lights.json", lights),
        ] {
            let p = dir.join(name);
            if name != "lights.json" || !p.exists() {
                fenestra_core::fs::write_atomically(&p, |tmp| std::fs::write(tmp, text))
                    .map_err(|e| RelightError::Store(e.to_string()))?;
            }
        }
        Ok(Store {
            dir: dir.to_path_buf(),
            manifest,
        })
    }

    /// The precomputation in `dir`.
    pub fn open(dir: &Path) -> Result<Self, RelightError> {
        let path = dir.join("relight.json");
        let text = std::fs::read_to_string(&path).map_err(|e| {
            RelightError::Store(format!(
                "{}: {e} (not a folder made by `fenestra relight precompute`?)",
                path.display()
            ))
        })?;
        let manifest: Manifest = serde_json::from_str(&text).map_err(|e| {
            RelightError::Store(format!(
                "{}:{}:{}: {e}",
                path.display(),
                e.line(),
                e.column()
            ))
        })?;
        if manifest.version != VERSION {
            return Err(RelightError::Store(format!(
                "{}: version {}, this build reads {VERSION}",
                path.display(),
                manifest.version
            )));
        }
        Ok(Store {
            dir: dir.to_path_buf(),
            manifest,
        })
    }

    /// Where frame `f` is kept.
    pub fn frame_path(&self, f: u32) -> PathBuf {
        self.dir.join("frames").join(format!("{f:04}.rlf"))
    }

    /// Whether frame `f` is finished: its file reads whole and has the manifest's size.
    pub fn done(&self, f: u32) -> bool {
        frame_file::read(&self.frame_path(f)).is_ok_and(|(h, _)| {
            (h.width, h.height, h.gather)
                == (
                    self.manifest.width,
                    self.manifest.height,
                    self.manifest.gather,
                )
        })
    }

    /// The animation's JSON as stored.
    pub fn animation_path(&self) -> PathBuf {
        self.dir.join("animation.json")
    }

    /// The lights file written beside the precomputation.
    pub fn lights_path(&self) -> PathBuf {
        self.dir.join("lights.json")
    }
}
