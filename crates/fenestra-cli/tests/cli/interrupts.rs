//! Interrupted renders, estimates and benches keep what they have and never replace a complete result.

use super::*;

#[cfg(unix)]
#[test]
fn interrupting_a_render_keeps_what_it_has() {
    for signal in ["INT", "TERM"] {
        interrupt_render(signal);
    }
}

/// An interrupted re-render never replaces a complete image (or a split render's complete
/// part, whose .film merge would then refuse): it goes beside it, to OUT.interrupted.exr.
#[cfg(unix)]
#[test]
fn an_interrupted_rerender_keeps_the_complete_image() {
    let out = tmp("complete.exr");
    let o = out.to_str().expect("utf-8");
    let args = |spp: &'static str| {
        [
            "render",
            "builtin:box-hole",
            "--samples",
            spp,
            "--resolution",
            "32x32",
            "-q",
            "-o",
            o,
        ]
    };
    let done = fenestra(&args("0..4"));
    assert!(
        done.status.success(),
        "{}",
        String::from_utf8_lossy(&done.stderr)
    );
    let files = |exr: &Path| {
        ["exr", "json", "film"].map(|e| std::fs::read(exr.with_extension(e)).expect("file"))
    };
    let before = files(&out);
    let err = interrupted(&args("0..100000000"));
    assert!(err.contains("holds a complete render"), "{err}");
    assert!(files(&out) == before, "the complete part was replaced");
    let beside = out.with_extension("interrupted.exr");
    assert!(
        Image::read(&beside)
            .expect("the interrupted render")
            .mean()
            .r
            > 0.0
    );
    assert!(beside.with_extension("film").exists());
}

/// Each snapshot goes where an interrupted render would when it is written: a render that
/// completes at the same OUT meanwhile is replaced neither by the later snapshots nor by the
/// interrupted result (issue 68 item 7: both landed over it).
#[cfg(unix)]
#[test]
fn snapshots_never_replace_a_render_completed_meanwhile() {
    let out = tmp("meanwhile.exr");
    let o = out.to_str().expect("utf-8");
    let render = |spp: &'static str| {
        [
            "render",
            "builtin:box-hole",
            "--spp",
            spp,
            "--resolution",
            "32x32",
            "-q",
            "-o",
            o,
        ]
    };
    let long = Command::new(env!("CARGO_BIN_EXE_fenestra"))
        .args(render("100000000"))
        .args(["--snapshot-every", "0.5"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("spawn");
    let pause = || std::thread::sleep(std::time::Duration::from_millis(1200));
    pause();
    let sidecar = out.with_extension("json");
    assert!(
        sidecar.exists(),
        "the long render's snapshots go to OUT at first"
    );
    let done = fenestra(&render("4"));
    assert!(
        done.status.success(),
        "{}",
        String::from_utf8_lossy(&done.stderr)
    );
    let files =
        || ["exr", "json", "png"].map(|e| std::fs::read(out.with_extension(e)).expect("file"));
    let complete = files();
    pause();
    let stopped = signal_after_a_while(long, "INT");
    let err = String::from_utf8_lossy(&stopped.stderr);
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    assert!(
        files() == complete,
        "the render completed meanwhile was replaced: {err}"
    );
    assert!(err.contains("holds a complete render"), "{err}");
    assert!(out.with_extension("interrupted.exr").exists());
}

/// Renders for a while, sends `signal` as Ctrl-C or a job scheduler would: the samples taken
/// so far are written and the exit status is 130.
#[cfg(unix)]
fn interrupt_render(signal: &str) {
    let out = tmp(&format!("interrupted-{signal}.exr"));
    let child = Command::new(env!("CARGO_BIN_EXE_fenestra"))
        .args([
            "render",
            "builtin:box-hole",
            "--spp",
            "100000",
            "--resolution",
            "32x32",
            "--json",
            "-o",
            out.to_str().expect("utf-8"),
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("spawn");
    // Let it take some samples, then send the signal as Ctrl-C would.
    let o = signal_after_a_while(child, signal);
    assert_eq!(
        o.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).expect("summary");
    assert_eq!(s["interrupted"], true);
    assert!(s["spp"].as_u64().expect("spp") >= 1 && s["spp"].as_u64().expect("spp") < 100000);
    let img = Image::read(&out).expect("partial image written");
    assert!(img.mean().r > 0.0);
}

/// Ctrl-C while `portals` traces photons exits 130 and keeps the portals file and picture
/// of an earlier, complete estimate as they were (it wrote portals of the photons so far,
/// and exited 0).
#[cfg(unix)]
#[test]
fn an_interrupted_portal_estimate_keeps_the_complete_one() {
    let out = tmp("kept-portals.json");
    let o = out.to_str().expect("utf-8");
    let done = fenestra(&["portals", "builtin:box-hole", "-q", "-o", o]);
    assert!(
        done.status.success(),
        "{}",
        String::from_utf8_lossy(&done.stderr)
    );
    let before = (
        std::fs::read(&out).expect("json"),
        std::fs::read(out.with_extension("svg")).expect("svg"),
    );
    let err = interrupted(&[
        "portals",
        "builtin:box-hole",
        "--photons",
        "100000000",
        "--settle",
        "0",
        "--max-beams",
        "4294967295",
        "--time",
        "0",
        "-q",
        "-o",
        o,
    ]);
    assert!(err.contains("nothing written"), "{err}");
    let after = (
        std::fs::read(&out).expect("json"),
        std::fs::read(out.with_extension("svg")).expect("svg"),
    );
    assert!(before == after, "the complete estimate was replaced");
}

/// Ctrl-C during a suite stops it after the current run, reports what finished, says how to
/// resume and exits 130; running it again does the rest.
#[test]
#[cfg(unix)]
fn an_interrupted_bench_says_how_to_resume() {
    let (dir, _, args) = bench_suite(
        "bench-interrupted",
        "name = \"stop\"\nresolution = [32, 32]\nrepetitions = 6\n[reference]\n\
         integrator = \"af_hf\"\nspp = 16\n[[scene]]\nscene = \"builtin:box-hole\"\n\
         max_depth = [3]\n[[technique]]\nlabel = \"AF\"\nintegrator = \"af_hf\"\n\
         [[budget]]\nspp = 256\n",
    );
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let child = Command::new(env!("CARGO_BIN_EXE_fenestra"))
        .args(&args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("spawn");
    let results = dir.join("results.jsonl");
    let lines = || {
        std::fs::read_to_string(&results)
            .map(|t| t.lines().count())
            .unwrap_or(0)
    };
    let start = std::time::Instant::now();
    while lines() == 0 && start.elapsed().as_secs() < 120 {
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    // Only the bench process: its current run finishes, then it stops.
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(kill.success());
    let o = child.wait_with_output().expect("wait");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted; run the same command again to resume"),
        "{err}"
    );
    let finished = lines();
    assert!((1..6).contains(&finished), "{finished} runs finished");
    assert!(
        dir.join("index.html").exists(),
        "the report shows what finished"
    );
    let o = fenestra(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(lines(), 6, "the rest is run, nothing twice");
}
