//! Any bytes given to the pbrt-v4 reader must give a scene or an error, never a panic, and
//! what loads must build, or be refused cleanly, with both ray-query backends. The file name
//! puts relative Include/plymesh/texture paths in a folder that does not exist.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let path = Path::new("/nonexistent-fenestra-fuzz/scene.pbrt");
    if let Ok(loaded) = fenestra_pbrt::load_bytes(data, path, false) {
        for backend in fenestra_scene::Backend::available() {
            let _ = fenestra_scene::Scene::build(loaded.desc.clone(), backend);
        }
    }
});
