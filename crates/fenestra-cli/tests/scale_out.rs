//! Scale-out: renders split by sample ranges and by tiles merge into the single render bit
//! for bit, whatever the split and the merge order; bad parts are refused with clear errors
//! and nothing is overwritten; `fenestra split` writes jobs that Open Job Description and
//! bash accept, and the OpenJD job run here makes the single render's image.

mod common;

use common::fenestra;
use fenestra_core::image::Image;
use fenestra_render::film_file;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn ok(o: Output) -> Output {
    assert!(
        o.status.success(),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

fn refused(o: Output) -> String {
    assert!(!o.status.success(), "should fail");
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fenestra-scale-out-{}/{name}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8")
}

/// `render SCENE` at 20x14 with `extra`, to `out`.
fn render(scene: &str, integrator: &str, out: &Path, extra: &[&str]) {
    let mut args = vec![
        "render",
        scene,
        "--integrator",
        integrator,
        "--resolution",
        "20x14",
        "--quiet",
        "-o",
        s(out),
    ];
    args.extend_from_slice(extra);
    ok(fenestra(&args));
}

/// Asserts that two renders hold the same film (sums, squares and counts) and image, bit for
/// bit.
fn assert_same(single: &Path, merged: &Path) {
    let (_, a) = film_file::read(&single.with_extension("film")).expect("single film");
    let (_, b) = film_file::read(&merged.with_extension("film")).expect("merged film");
    assert_eq!(a.window, b.window);
    assert!(
        a.pixels == b.pixels && a.splats == b.splats && a.light_paths == b.light_paths,
        "{} differs from {}",
        merged.display(),
        single.display()
    );
    let (x, y) = (
        Image::read(single).expect("exr"),
        Image::read(merged).expect("exr"),
    );
    let bits = |i: &Image| -> Vec<u32> {
        i.pixels
            .iter()
            .flat_map(|p| p.to_array().map(f32::to_bits))
            .collect()
    };
    assert_eq!(bits(&x), bits(&y));
}

/// Path tracers and, with their light paths' splats, lt and lp_lt (on the glossy room lit by
/// the sun through its window; lp_lt's light paths started where a pilot learned).
#[test]
fn sample_ranges_merge_into_the_single_render_bit_for_bit() {
    const SPP: u32 = 14;
    let splits: [&[u32]; 4] = [&[], &[5], &[1, 9], &[2, 3, 4, 8, 9, 13]];
    let window = dir("window").join("portals.json");
    ok(fenestra(&[
        "portals",
        "builtin:glossy-room",
        "--time",
        "0",
        "--quiet",
        "-o",
        s(&window),
    ]));
    let through_window = ["--portals", s(&window)];
    // lp_lt's parts each learn the same emission before their samples (light paths always:
    // on so small an image the trial measures them at 0.96x and turns them off).
    let learned = [
        "--portals",
        s(&window),
        "--light-paths-pilot",
        "4096",
        "--light-paths-trial",
        "0",
    ];
    for (integrator, scene, extra) in [
        ("hf", "builtin:box-hole", &[][..]),
        ("af_hf", "builtin:box-hole", &[]),
        ("lp_hf", "builtin:box-4holes", &[]),
        ("lt", "builtin:glossy-room", &through_window),
        ("lp_lt", "builtin:glossy-room", &learned),
    ] {
        let render = |scene: &str, integrator: &str, out: &Path, more: &[&str]| {
            render(scene, integrator, out, &[extra, more].concat());
        };
        let d = dir(integrator);
        let single = d.join("single.exr");
        render(scene, integrator, &single, &["--samples", "0..14"]);
        if integrator.ends_with("lt") {
            let (_, film) = film_file::read(&single.with_extension("film")).expect("film");
            assert!(film.light_paths > 0 && film.splats.iter().any(|p| p.count > 0));
        }
        // An ordinary render makes the same image.
        let plain = d.join("plain.exr");
        render(scene, integrator, &plain, &["--spp", "14"]);
        assert_eq!(
            Image::read(&plain).expect("exr").pixels,
            Image::read(&single).expect("exr").pixels
        );
        for cuts in splits {
            let bounds: Vec<u32> = [0]
                .into_iter()
                .chain(cuts.iter().copied())
                .chain([SPP])
                .collect();
            let mut parts: Vec<PathBuf> = bounds
                .windows(2)
                .map(|w| {
                    let p = d.join(format!("p{}-{}.exr", w[0], w[1]));
                    render(
                        scene,
                        integrator,
                        &p,
                        &["--samples", &format!("{}..{}", w[0], w[1])],
                    );
                    p.with_extension("film")
                })
                .collect();
            // Shuffled: the merge must not depend on the order.
            let half = parts.len() / 2;
            parts.rotate_left(half);
            parts.reverse();
            let merged = d.join(format!("merged-{}.exr", parts.len()));
            let mut args = vec!["merge", "--total", "14", "-o", s(&merged)];
            args.extend(parts.iter().map(|p| s(p)));
            ok(fenestra(&args));
            assert_same(&single, &merged);
        }
    }
}

#[test]
fn tiles_merge_into_the_single_render_for_path_tracers_and_ias() {
    let d = dir("tiles");
    // Any tiles for a path tracer: an L-shaped cut into three pieces.
    let single = d.join("single.exr");
    render("builtin:box-hole", "af_hf", &single, &["--samples", "0..6"]);
    let mut parts = Vec::new();
    for (i, crop) in ["0,0,7,14", "7,0,20,5", "7,5,20,14"].iter().enumerate() {
        let p = d.join(format!("t{i}.exr"));
        render(
            "builtin:box-hole",
            "af_hf",
            &p,
            &["--samples", "0..6", "--crop", crop],
        );
        parts.push(p);
    }
    let merged = d.join("merged.exr");
    ok(fenestra(&[
        "merge",
        s(&parts[2]),
        s(&parts[0]),
        s(&parts[1]),
        "-o",
        s(&merged),
    ]));
    assert_same(&single, &merged);
    // A real scene (Bitterli's Cornell box, pbrt-v4) in four tiles of two sample ranges.
    let scene =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/cornell-box/scene-v4.pbrt");
    let single = d.join("real.exr");
    render(s(&scene), "af_hf", &single, &["--samples", "0..4"]);
    let mut parts = Vec::new();
    for (i, (crop, samples)) in [
        ("0,0,20,6", "0..4"),
        ("0,6,20,14", "0..1"),
        ("0,6,20,14", "1..4"),
    ]
    .iter()
    .enumerate()
    {
        let p = d.join(format!("real{i}.exr"));
        render(
            s(&scene),
            "af_hf",
            &p,
            &["--samples", samples, "--crop", crop],
        );
        parts.push(p);
    }
    let merged = d.join("real-merged.exr");
    ok(fenestra(&[
        "merge",
        s(&parts[1]),
        s(&parts[2]),
        s(&parts[0]),
        "--total",
        "4",
        "-o",
        s(&merged),
    ]));
    assert_same(&single, &merged);
    // ias renders 8x8 blocks as wholes: bands on the block grid, and the whole as one tile.
    let single = d.join("ias.exr");
    render(
        "builtin:kitchen-72",
        "ias",
        &single,
        &["--crop", "0,0,20,14"],
    );
    let (a, b) = (d.join("ias-a.exr"), d.join("ias-b.exr"));
    render("builtin:kitchen-72", "ias", &a, &["--crop", "0,0,20,8"]);
    render("builtin:kitchen-72", "ias", &b, &["--crop", "0,8,20,14"]);
    let merged = d.join("ias-merged.exr");
    ok(fenestra(&["merge", s(&b), s(&a), "-o", s(&merged)]));
    assert_same(&single, &merged);
    let e = refused(fenestra(&[
        "render",
        "builtin:kitchen-72",
        "--integrator",
        "ias",
        "--resolution",
        "20x14",
        "--crop",
        "0,3,20,14",
        "-o",
        s(&d.join("x.exr")),
    ]));
    assert!(e.contains("multiples of 8"), "{e}");
    let e = refused(fenestra(&[
        "render",
        "builtin:kitchen-72",
        "--integrator",
        "ias",
        "--samples",
        "0..4",
        "-o",
        s(&d.join("x.exr")),
    ]));
    assert!(e.contains("split it by tiles"), "{e}");
    // Light paths bring light to every tile: lt splits by sample ranges only.
    let e = refused(fenestra(&[
        "render",
        "builtin:glossy-room",
        "--integrator",
        "lt",
        "--crop",
        "0,0,8,8",
        "-o",
        s(&d.join("x.exr")),
    ]));
    assert!(e.contains("--crop cannot cut a tile of lt's render"), "{e}");
    assert!(e.contains("split it by sample ranges (--samples)"), "{e}");
}

#[test]
fn bad_parts_are_refused_and_nothing_is_overwritten() {
    let d = dir("refusals");
    let part = |name: &str, extra: &[&str]| {
        let p = d.join(name);
        render("builtin:box-hole", "af_hf", &p, extra);
        p.with_extension("film")
    };
    let a = part("a.exr", &["--samples", "0..4"]);
    let b = part("b.exr", &["--samples", "3..8"]);
    let c = part("c.exr", &["--samples", "4..8"]);
    let other_seed = part("seed.exr", &["--samples", "4..8", "--seed", "9"]);
    let other_scene = d.join("scene.exr");
    render(
        "builtin:box-4holes",
        "af_hf",
        &other_scene,
        &["--samples", "4..8"],
    );
    let out = d.join("out.exr");
    ok(fenestra(&["merge", s(&a), s(&c), "-o", s(&out)]));
    let before = std::fs::read(&out).expect("merged");
    let merge = |parts: &[&Path], extra: &[&str]| {
        let mut args = vec!["merge", "-o", s(&out)];
        args.extend(parts.iter().map(|p| s(p)));
        args.extend_from_slice(extra);
        refused(fenestra(&args))
    };
    let e = merge(&[&a, &b], &[]);
    assert!(e.contains("overlap") && e.contains("samples 3..4"), "{e}");
    let e = merge(&[&a, &other_seed], &[]);
    assert!(e.contains("not parts of one render: seed 0 vs 9"), "{e}");
    let e = merge(&[&a, &other_scene.with_extension("film")], &[]);
    assert!(
        e.contains("not parts of one render: scene box-hole vs box-4holes"),
        "{e}"
    );
    let e = merge(&[&a, &c], &["--total", "12"]);
    assert!(e.contains("samples 8..12 are missing"), "{e}");
    let e = merge(&[&c], &["--total", "8"]);
    assert!(e.contains("samples 0..4 are missing"), "{e}");
    // Truncated, and one flipped bit in the pixels.
    let bytes = std::fs::read(&c).expect("part");
    let truncated = d.join("truncated.film");
    std::fs::write(&truncated, &bytes[..bytes.len() - 50]).expect("write");
    let e = merge(&[&a, &truncated], &[]);
    assert!(e.contains("truncated or corrupt"), "{e}");
    let mut flipped = bytes.clone();
    let at = bytes.len() - 500;
    flipped[at] ^= 4;
    let corrupt = d.join("corrupt.film");
    std::fs::write(&corrupt, &flipped).expect("write");
    let e = merge(&[&a, &corrupt], &[]);
    assert!(e.contains("checksum does not match"), "{e}");
    let e = merge(&[&d.join("a.png")], &[]);
    assert!(e.contains("not a usable film-state file"), "{e}");
    assert_eq!(
        std::fs::read(&out).expect("still there"),
        before,
        "a refused merge wrote"
    );
}

/// Parts whose checksum was recomputed after their pixels or header were changed (a forgery,
/// or damage repaired by a tool) are refused by what is impossible in them; a damaged header
/// is called damaged; one tile alone is a partial image only when asked for.
#[test]
fn forged_damaged_and_partial_parts_are_refused() {
    let d = dir("forged");
    let a = d.join("a.exr");
    render("builtin:box-hole", "af_hf", &a, &["--samples", "0..4"]);
    let c = d.join("c.exr");
    render("builtin:box-hole", "af_hf", &c, &["--samples", "4..8"]);
    let (a, c) = (a.with_extension("film"), c.with_extension("film"));
    let out = d.join("out.exr");
    let merge = |parts: &[&Path], extra: &[&str]| {
        let mut args = vec!["merge", "-o", s(&out)];
        args.extend(parts.iter().map(|p| s(p)));
        args.extend_from_slice(extra);
        fenestra(&args)
    };
    let (header, film) = film_file::read(&c).expect("part");
    let forge = |name: &str, change: &dyn Fn(&mut fenestra_render::Film)| {
        let mut forged = film.clone();
        change(&mut forged);
        let path = d.join(name);
        film_file::write(&path, &header, &forged).expect("write");
        path
    };
    // Sums near the 128-bit limit: they would wrap to a pixel of -1e18.
    let huge = forge("huge.film", &|f| f.pixels[5].sum[0] = i128::MAX / 2);
    let e = refused(merge(&[&a, &huge], &[]));
    assert!(
        e.contains("damaged or forged: pixel (5, 0) has sums beyond what its 4 samples"),
        "{e}"
    );
    // A sample count at the u32 limit: it would wrap to fewer samples than taken.
    let many = forge("many.film", &|f| f.pixels[30].count = u32::MAX);
    let e = refused(merge(&[&a, &many], &[]));
    assert!(
        e.contains("holds 4294967295 samples, its part at most 4"),
        "{e}"
    );
    // Every pixel emptied: a part that did not drop its samples must hold them.
    let empty = forge("empty.film", &|f| f.pixels.fill(Default::default()));
    let e = refused(merge(&[&a, &empty], &[]));
    assert!(
        e.contains("its pixels lack 1120 of their samples, and it dropped 0"),
        "{e}"
    );
    // A lit pixel's sum made 10x larger than its samples' squares allow.
    let lit = film
        .pixels
        .iter()
        .position(|p| p.sum[1] > 0)
        .expect("a lit pixel");
    let scaled = forge("scaled.film", &|f| f.pixels[lit].sum[1] *= 10);
    let e = refused(merge(&[&a, &scaled], &[]));
    assert!(
        e.contains("has sums that no 4 samples with its sums of squares can have"),
        "{e}"
    );
    // One flipped byte in the header's key, the checksum left as it was.
    let mut bytes = std::fs::read(&c).expect("part");
    let at = bytes
        .windows(7)
        .position(|w| w == b"\"key\":\"")
        .expect("key")
        + 7;
    bytes[at] = if bytes[at] == b'0' { b'1' } else { b'0' };
    let flipped = d.join("flipped.film");
    std::fs::write(&flipped, &bytes).expect("write");
    let e = refused(merge(&[&a, &flipped], &[]));
    assert!(e.contains("damaged: its checksum does not match"), "{e}");
    assert!(!e.contains("differs"), "{e}");
    // A tile alone: refused unless --partial.
    let tile = d.join("tile.exr");
    render("builtin:box-hole", "af_hf", &tile, &["--crop", "0,0,8,8"]);
    let tile = tile.with_extension("film");
    let e = refused(merge(&[&tile], &[]));
    assert!(e.contains("cover pixels 0,0,8,8 of a 20x14 image"), "{e}");
    assert!(!out.exists(), "a refused merge wrote");
    ok(merge(&[&tile], &["--partial"]));
    assert_eq!(Image::read(&out).expect("merged").width, 8);
}

/// A virtual environment with openjd-cli (made once for all tests), or why there is none.
fn openjd() -> Result<PathBuf, String> {
    static VENV: std::sync::OnceLock<Result<PathBuf, String>> = std::sync::OnceLock::new();
    VENV.get_or_init(install_openjd).clone()
}

fn install_openjd() -> Result<PathBuf, String> {
    let venv = std::env::temp_dir().join("fenestra-openjd-venv");
    let bin = venv.join("bin/openjd");
    if bin.exists() {
        return Ok(bin);
    }
    let run = |cmd: &mut Command| -> Result<(), String> {
        let o = cmd.output().map_err(|e| e.to_string())?;
        o.status
            .success()
            .then_some(())
            .ok_or_else(|| String::from_utf8_lossy(&o.stderr).into_owned())
    };
    run(Command::new("python3").args(["-m", "venv", s(&venv)]))?;
    run(Command::new(venv.join("bin/pip")).args(["install", "--quiet", "openjd-cli"]))?;
    Ok(bin)
}

/// Checks the OpenJD template and runs its steps up to `step` on this machine; false (and a
/// message) where openjd-cli cannot be installed.
fn openjd_runs(template: &Path, step: &str) -> bool {
    let bin = match openjd() {
        Ok(bin) => bin,
        Err(why) => {
            eprintln!("SKIPPED: openjd-cli cannot be installed from PyPI here ({why})");
            return false;
        }
    };
    ok(Command::new(&bin)
        .arg("check")
        .arg(template)
        .output()
        .expect("openjd"));
    ok(Command::new(&bin)
        .args(["run", s(template), "--step", step, "--run-dependencies"])
        .output()
        .expect("openjd"));
    true
}

/// Asserts that bash parses each script in `dir`.
fn assert_bash_parses(dir: &Path, scripts: &[&str]) {
    for script in scripts {
        let o = Command::new("bash")
            .arg("-n")
            .arg(dir.join(script))
            .output()
            .expect("bash");
        assert!(
            o.status.success(),
            "{script}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

#[test]
fn split_writes_jobs_that_openjd_and_slurm_accept_and_that_render_the_single_image() {
    let d = dir("split");
    let render_args = [
        "builtin:box-hole",
        "--spp",
        "9",
        "--resolution",
        "20x14",
        "--integrator",
        "af_hf",
    ];
    let slurm = d.join("slurm");
    let mut args = vec![
        "split",
        "--parts",
        "3",
        "--engine",
        "slurm",
        "-o",
        s(&slurm),
    ];
    args.extend_from_slice(&render_args);
    ok(fenestra(&args));
    assert_bash_parses(&slurm, &["render.sbatch", "merge.sbatch", "submit.sh"]);
    let text = std::fs::read_to_string(slurm.join("render.sbatch")).expect("script");
    assert!(text.contains("#SBATCH --array=0-2") && text.contains("pieces=(0..3 3..6 6..9)"));
    let submit = std::fs::read_to_string(slurm.join("submit.sh")).expect("script");
    assert!(submit.contains("--dependency=afterok:"));
    let e = refused(fenestra(&[
        "split",
        "--parts",
        "2",
        "--engine",
        "slurm",
        "-o",
        s(&slurm),
        "builtin:kitchen-72",
        "--integrator",
        "ias",
    ]));
    assert!(e.contains("ias decides its own samples"), "{e}");

    let job = d.join("openjd");
    let mut args = vec!["split", "--parts", "3", "--engine", "openjd", "-o", s(&job)];
    args.extend_from_slice(&render_args);
    ok(fenestra(&args));
    if !openjd_runs(&job.join("template.json"), "Merge") {
        return;
    }
    let single = d.join("single.exr");
    render("builtin:box-hole", "af_hf", &single, &["--samples", "0..9"]);
    assert_same(&single, &job.join("merged.exr"));
}

#[test]
fn a_bench_suite_runs_as_a_job_of_references_runs_and_report() {
    let d = dir("bench-job");
    let suite = d.join("suite.toml");
    std::fs::write(
        &suite,
        "name = \"job\"\nresolution = [8, 8]\n[reference]\nintegrator = \"af_hf\"\nspp = 32\n\
         [[scene]]\nscene = \"builtin:box-hole\"\nmax_depth = [2, 3]\n[[technique]]\n\
         label = \"HF\"\nintegrator = \"hf\"\n[[technique]]\nlabel = \"AF\"\n\
         integrator = \"af_hf\"\n[[budget]]\nspp = 4\n",
    )
    .expect("suite");
    let (out, cache) = (d.join("report"), d.join("cache"));
    let job = |engine: &str, dir: &Path| {
        ok(fenestra(&[
            "bench",
            s(&suite),
            "-o",
            s(&out),
            "--cache",
            s(&cache),
            "--engine",
            engine,
            "--job",
            s(dir),
        ]))
    };
    let slurm = d.join("slurm");
    job("slurm", &slurm);
    assert_bash_parses(
        &slurm,
        &[
            "references.sbatch",
            "runs.sbatch",
            "report.sbatch",
            "submit.sh",
        ],
    );
    let runs = std::fs::read_to_string(slurm.join("runs.sbatch")).expect("script");
    assert!(runs.contains("#SBATCH --array=0-3"), "{runs}");
    let openjd_job = d.join("openjd");
    job("openjd", &openjd_job);
    if !openjd_runs(&openjd_job.join("template.json"), "Report") {
        return;
    }
    let records = std::fs::read_dir(out.join("results.d"))
        .expect("records")
        .count();
    assert_eq!(records, 4, "a record per run");
    let table = std::fs::read_to_string(out.join("table.md")).expect("report");
    assert!(
        table.contains("| builtin:box-hole | 3 | 4spp | AF |"),
        "{table}"
    );
}
