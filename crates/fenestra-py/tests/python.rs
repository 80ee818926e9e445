//! Runs the Python module's pytest suite (tests/python/) against the extension module this
//! build made, staged beside the package's Python sources as an installed wheel would lay
//! them out; the suite compares it with this build's `fenestra` binary.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The folder holding this build's artifacts (target/debug): the test runs from its deps/.
fn artifacts() -> PathBuf {
    let exe = std::env::current_exe().expect("the test's own path");
    exe.parent()
        .and_then(Path::parent)
        .expect("the test runs from target/<profile>/deps")
        .to_path_buf()
}

/// The package `fenestra` as a wheel installs it: its Python files and the extension
/// module, in a folder of `root`.
fn stage(root: &Path) -> PathBuf {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    let package = root.join("fenestra");
    std::fs::create_dir_all(&package).expect("a folder for the staged package");
    for entry in std::fs::read_dir(manifest.join("python/fenestra")).expect("python/fenestra") {
        let path = entry.expect("a package file").path();
        if path.extension().is_some_and(|e| e == "py") {
            std::fs::copy(&path, package.join(path.file_name().expect("a file name")))
                .expect("copying a package file");
        }
    }
    // A library a test depends on stays in deps/ (a cdylib without a hash in its name).
    let native = artifacts().join("deps/libfenestra_native.so");
    assert!(
        native.exists(),
        "{} was not built (the fenestra-py library's cdylib)",
        native.display()
    );
    std::fs::copy(&native, package.join("_native.abi3.so")).expect("copying the extension");
    root.to_path_buf()
}

#[test]
fn the_python_suite_passes() {
    let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    let ready = Command::new(&python)
        .args(["-c", "import numpy, pytest"])
        .status()
        .is_ok_and(|s| s.success());
    assert!(
        ready,
        "{python} with numpy and pytest is needed for the Python module's tests: run scripts/setup"
    );
    let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fenestra-py");
    let _ = std::fs::remove_dir_all(&root);
    let staged = stage(&root);
    let binary = artifacts().join("fenestra");
    assert!(binary.exists(), "{} was not built", binary.display());
    let suite = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/python");
    let status = Command::new(&python)
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
        .arg(&suite)
        .env("PYTHONPATH", &staged)
        .env("FENESTRA_BIN", &binary)
        .env(
            "FENESTRA_DOCS",
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs"),
        )
        .status()
        .expect("running pytest");
    assert!(
        status.success(),
        "the Python module's pytest suite failed (above)"
    );
}
