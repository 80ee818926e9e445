//! Any bytes as a PLY or an OBJ file (the first byte picks which) must give a mesh or an
//! error, never a panic; what reads must stage as a scene and build with both backends.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&kind, bytes)) = data.split_first() else {
        return;
    };
    let ext = if kind % 2 == 0 { "ply" } else { "obj" };
    // One file per fuzzing process, in memory where the system has it.
    let dir = if std::path::Path::new("/dev/shm").is_dir() { "/dev/shm" } else { "/tmp" };
    let path = std::path::PathBuf::from(format!("{dir}/fenestra-fuzz-{}.{ext}", std::process::id()));
    if std::fs::write(&path, bytes).is_err() {
        return;
    }
    if let Ok((desc, _)) = fenestra_scene::mesh::viewer_scene(&path) {
        for backend in fenestra_scene::Backend::available() {
            let _ = fenestra_scene::Scene::build(desc.clone(), backend);
        }
    }
});
