//! What the pbrt-v4 input tests share: loading text, scratch folders, what a pixel sees.
#![allow(dead_code)]

use fenestra_core::Vec2;
use fenestra_pbrt::{self as pbrt, Loaded};
use fenestra_scene::Scene;
use std::path::{Path, PathBuf};

pub fn load(text: &str) -> Result<Loaded, String> {
    pbrt::load_bytes(text.as_bytes(), Path::new("test.pbrt"), false).map_err(|e| e.to_string())
}

pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fenestra-pbrt-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("scratch dir");
    d
}

/// Which shape the ray through film position (x, y) of a w x h image hits first.
pub fn shape_at(scene: &Scene, x: f32, y: f32) -> Option<u32> {
    let (w, h) = (scene.defaults.width, scene.defaults.height);
    let ray = scene
        .camera
        .generate_ray(Vec2::new(x * w as f32, y * h as f32), w, h);
    scene.intersect(&ray, f32::INFINITY).map(|hit| hit.shape)
}
