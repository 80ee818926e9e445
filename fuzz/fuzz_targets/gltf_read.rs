//! Any bytes as a .gltf or .glb file (the first byte picks which) must give a scene or an
//! error, never a panic; what reads must build with both backends.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&kind, bytes)) = data.split_first() else {
        return;
    };
    let ext = if kind % 2 == 0 { "gltf" } else { "glb" };
    let dir = if std::path::Path::new("/dev/shm").is_dir() { "/dev/shm" } else { "/tmp" };
    let path = std::path::PathBuf::from(format!("{dir}/fenestra-fuzz-{}.{ext}", std::process::id()));
    if std::fs::write(&path, bytes).is_err() {
        return;
    }
    if let Ok(loaded) = fenestra_gltf::load(&path, None) {
        for backend in fenestra_scene::Backend::available() {
            let _ = fenestra_scene::Scene::build(loaded.desc.clone(), backend);
        }
    }
});
