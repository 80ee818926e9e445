//! What the command-line tests share: running the binary, scratch files, refusals and
//! interrupted runs. Each test binary uses some of it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn fenestra(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_fenestra"))
        .args(args)
        .output()
        .expect("run fenestra")
}

pub fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fenestra-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

pub fn render(out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "render",
        "builtin:box-hole",
        "--spp",
        "4",
        "--resolution",
        "24x16",
        "-o",
        out.to_str().expect("utf-8"),
    ];
    args.extend_from_slice(extra);
    fenestra(&args)
}

pub fn assert_clear_error(args: &[&str], expect: &str) {
    let o = fenestra(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{args:?} should fail");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert!(
        err.contains(expect),
        "{args:?}: expected '{expect}' in: {err}"
    );
}

/// `fenestra compare --ref REFERENCE IMAGE` fails, saying `expect`.
pub fn assert_compare_refused(reference: &Path, image: &Path, expect: &str) {
    let path = |p: &Path| p.to_str().expect("utf-8").to_string();
    assert_clear_error(
        &["compare", "--ref", &path(reference), &path(image)],
        expect,
    );
}

/// Runs `fenestra ARGS` and sends it SIGINT after a while: it must exit 130; its stderr.
#[cfg(unix)]
pub fn interrupted(args: &[&str]) -> String {
    let child = Command::new(env!("CARGO_BIN_EXE_fenestra"))
        .args(args)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("spawn");
    let stopped = signal_after_a_while(child, "INT");
    let err = String::from_utf8_lossy(&stopped.stderr).into_owned();
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    err
}

/// Sends `signal` (INT, TERM) to `child` after 1.5 s of work and waits for it to end.
#[cfg(unix)]
pub fn signal_after_a_while(child: std::process::Child, signal: &str) -> Output {
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let kill = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(kill.success());
    child.wait_with_output().expect("wait")
}

/// A bench suite written beside a scratch report folder: (the folder, the suite file, the
/// `fenestra bench` arguments that run it with a cache inside the folder).
pub fn bench_suite(name: &str, toml: &str) -> (PathBuf, PathBuf, Vec<String>) {
    let dir = tmp(name);
    let suite = dir.with_extension("toml");
    std::fs::write(&suite, toml).expect("suite");
    let arg = |p: &Path| p.to_str().expect("utf-8").to_string();
    let args = vec![
        "bench".into(),
        arg(&suite),
        "-o".into(),
        arg(&dir),
        "--cache".into(),
        arg(&dir.join("cache")),
    ];
    (dir, suite, args)
}
