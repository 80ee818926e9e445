//! Turning the SCENE argument into a scene description.

use anyhow::{bail, Context, Result};
use fenestra_scene::{builtin, SceneDesc};
use std::path::Path;

/// `builtin:NAME` or a path to a scene file.
pub fn load(arg: &str) -> Result<SceneDesc> {
    if let Some(name) = arg.strip_prefix("builtin:") {
        return builtin::load(name).map_err(anyhow::Error::msg);
    }
    let path = Path::new(arg);
    std::fs::metadata(path).with_context(|| format!("cannot open scene file {arg}"))?;
    let names: Vec<String> = builtin::SCENES
        .iter()
        .map(|s| format!("builtin:{}", s.0))
        .collect();
    bail!(
        "{arg}: this build does not read scene files yet (pbrt-v4, OBJ and PLY input is planned); \
         render a built-in scene instead: {}",
        names.join(", ")
    )
}
