//! A relighting precomputation (seed 003 ch. 4) opened with its animated scene and the lights
//! to relight it under.

use crate::scene::{load, SceneRequest};
use anyhow::Context;
use fenestra_relight::animation::Animation;
use fenestra_relight::lights_file::LightsFile;
use fenestra_relight::sequence::AnimatedScene;
use fenestra_relight::store::Store;
use std::path::{Path, PathBuf};

/// A precomputation opened: the folder, its animated scene, the lights to relight with, and
/// every file that was read (outputs must not replace them).
pub struct Opened {
    pub store: Store,
    pub animated: AnimatedScene,
    pub lights: LightsFile,
    /// Every file it read.
    pub inputs: Vec<PathBuf>,
    /// What its scene asks for that fenestra replaces or leaves out.
    pub warnings: Vec<String>,
}

/// The precomputation in `dir`, its animated scene, and the lights of `lights` (default: the
/// folder's own lights file).
pub fn open(dir: &Path, lights: Option<&Path>) -> crate::Result<Opened> {
    let store = Store::open(dir).map_err(anyhow::Error::from)?;
    let animation_path = store.animation_path();
    let animation_text = std::fs::read_to_string(&animation_path)
        .with_context(|| format!("cannot read {}", animation_path.display()))?;
    let animation = Animation::parse(&animation_text, &animation_path.display().to_string())
        .map_err(anyhow::Error::from)?;
    let loaded = load(&SceneRequest::new(store.manifest.scene.clone()))?;
    let warnings = loaded.warnings();
    let animated = AnimatedScene::new(loaded.desc, animation).map_err(anyhow::Error::from)?;
    let lights_path = lights.map_or_else(|| store.lights_path(), Path::to_path_buf);
    let lights_text = std::fs::read_to_string(&lights_path)
        .with_context(|| format!("cannot read {}", lights_path.display()))?;
    let lights = LightsFile::parse(&lights_text, &lights_path.display().to_string())
        .map_err(anyhow::Error::from)?;
    let mut inputs = loaded.files;
    inputs.extend([animation_path, lights_path, dir.join("relight.json")]);
    Ok(Opened {
        store,
        animated,
        lights,
        inputs,
        warnings,
    })
}
