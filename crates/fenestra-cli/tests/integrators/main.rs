//! Scenes and the research integrators from the command line: scene files and their export,
//! light portals (from the scene, a file, an estimate and its cache), ias and its work maps,
//! the learned light sampler.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use fenestra_core::image::Image;
use std::path::{Path, PathBuf};

mod many_lights;
mod portals;
mod scenes;
