//! Any bytes as a film-state file (the pieces `fenestra merge` reads) must read or be refused
//! with an error, never panic nor allocate beyond what the file's size allows; what reads
//! must merge with itself into a refusal (an overlap), not a crash.
#![no_main]

use fenestra_render::film_file;
use fenestra_render::merge::{self, Part};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let dir = if std::path::Path::new("/dev/shm").is_dir() { "/dev/shm" } else { "/tmp" };
    let path = std::path::PathBuf::from(format!("{dir}/fenestra-fuzz-{}.film", std::process::id()));
    if std::fs::write(&path, data).is_err() {
        return;
    }
    if film_file::read(&path).is_ok() {
        let part = Part::open(&path).expect("read once, opens again");
        let plan = merge::plan(&[part.clone()], None);
        if let Ok(plan) = plan {
            let _ = merge::merge(&[part.clone()], &plan);
        }
        assert!(merge::plan(&[part.clone(), part], None).is_err(), "a part overlaps itself");
    }
});
