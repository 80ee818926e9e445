//! pbrt-v4 materials, textures, spectra, lights, pixel filters and render settings as
//! fenestra reads them, and the values it refuses or clamps as pbrt-v4 does.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use fenestra_core::{Rgb, Vec2, Vec3};
use fenestra_pbrt as pbrt;
use fenestra_scene::light::{EnvironmentDesc, LightDesc};
use fenestra_scene::material;
use fenestra_scene::Material;

mod film_and_lights;
mod surfaces;
