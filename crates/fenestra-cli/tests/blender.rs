//! Runs the Blender add-on's pytest suite (blender/tests/) with the `bpy` module (Blender as
//! a Python module, from PyPI; CPython 3.11 only) against this build's fenestra binary.
//! `scripts/setup` installs bpy into its own virtual environment; where CPython 3.11 is not
//! to be had, the suite cannot run and the test says so and passes.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The Python that has bpy: $BPY_PYTHON, the one `scripts/setup` made, or python3.
fn bpy_python() -> Option<PathBuf> {
    let home = std::env::var_os("HOME").map(PathBuf::from);
    let candidates = std::env::var_os("BPY_PYTHON")
        .map(PathBuf::from)
        .into_iter()
        .chain(home.map(|h| h.join(".cache/fenestra/bpy-venv/bin/python")))
        .chain([PathBuf::from("python3")]);
    candidates.into_iter().find(|python| {
        Command::new(python)
            .args(["-c", "import bpy, pytest, OpenEXR"])
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

/// Whether a CPython 3.11 (the one bpy wheels are built for) is on PATH.
fn python_3_11_exists() -> bool {
    ["python3.11", "python3"].iter().any(|p| {
        Command::new(p)
            .args(["-c", "import sys; assert sys.version_info[:2] == (3, 11)"])
            .status()
            .is_ok_and(|s| s.success())
    })
}

#[test]
fn the_blender_add_on_suite_passes() {
    let Some(python) = bpy_python() else {
        assert!(
            !python_3_11_exists(),
            "CPython 3.11 is here but no Python with bpy, pytest and OpenEXR: run scripts/setup"
        );
        eprintln!("SKIPPED: the Blender add-on's tests need CPython 3.11 for the bpy module");
        return;
    };
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let user = Path::new(env!("CARGO_TARGET_TMPDIR")).join("blender-user");
    let _ = std::fs::remove_dir_all(&user);
    let status = Command::new(&python)
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
        .arg(repo.join("blender/tests"))
        .env("FENESTRA_BIN", env!("CARGO_BIN_EXE_fenestra"))
        .env("BLENDER_USER_RESOURCES", &user)
        .status()
        .expect("running pytest");
    assert!(
        status.success(),
        "the Blender add-on's suite failed (above)"
    );
}
