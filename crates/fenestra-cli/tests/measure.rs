//! Measuring from the command line: cached references, `compare`, bench suites and their
//! reports, the matrix tools (btf, lpca, prt), real scenes against their reference renders.

mod common;

use common::*;
use fenestra_core::image::{read_exr_metadata, Image};
use std::path::{Path, PathBuf};

#[test]
fn reference_is_cached_by_content_and_settings() {
    let cache = tmp("refcache");
    let run_with = |spp: &str, extra: &[&str]| {
        let mut args = vec![
            "reference",
            "builtin:box-hole",
            "--spp",
            spp,
            "--resolution",
            "8x8",
            "--cache",
            cache.to_str().expect("utf-8"),
            "--json",
        ];
        args.extend_from_slice(extra);
        let o = fenestra(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).expect("json")
    };
    let run = |spp: &str| run_with(spp, &[]);
    let first = run("16");
    assert_eq!(first["cached"], false);
    let again = run("16");
    assert_eq!(again["cached"], true);
    assert_eq!(first["path"], again["path"]);
    let other = run("32");
    assert_eq!(other["cached"], false, "other settings, other reference");
    assert_ne!(first["path"], other["path"]);
    // Every setting that changes the picture changes the key: the ray-query backend, the
    // integrator's own options.
    let lp = ["--integrator", "lp_hf"];
    let keyed = [
        run_with("16", &["--bvh", "obvhs"]),
        run_with("16", &lp),
        run_with("16", &[&lp[..], &["--portal-sampling", "area"]].concat()),
        run_with("16", &[&lp[..], &["--portal-light-mix", "0.5"]].concat()),
        run_with("16", &["--light-selection", "uniform"]),
    ];
    for (i, k) in keyed.iter().enumerate() {
        assert_eq!(k["cached"], false, "case {i}: {k}");
        assert_ne!(k["path"], first["path"], "case {i}");
    }
    let path = PathBuf::from(first["path"].as_str().expect("path"));
    assert!(
        path.with_extension("var.exr").exists(),
        "references carry their variance"
    );
    // References have a seed space of their own: --seed 0 renders with 2^40.
    let meta = read_exr_metadata(&path).expect("metadata");
    assert_eq!(
        meta.get("fenestra:seed").map(String::as_str),
        Some("1099511627776")
    );
    // A damaged cached reference is not served: it is rendered again.
    let bytes = std::fs::read(&path).expect("exr");
    std::fs::write(&path, &bytes[..bytes.len() / 2]).expect("truncate");
    assert_eq!(
        run("16")["cached"],
        false,
        "a truncated reference is rendered again"
    );
    assert_eq!(run("16")["cached"], true);
}

#[test]
fn compare_reports_metrics_and_efficiency() {
    let (reference, img) = (tmp("cmp-ref.exr"), tmp("cmp-img.exr"));
    let r = fenestra(&[
        "render",
        "builtin:box-hole",
        "--spp",
        "64",
        "--resolution",
        "24x16",
        "-o",
        reference.to_str().expect("utf-8"),
    ]);
    assert!(r.status.success());
    assert!(render(&img, &[]).status.success());
    let o = fenestra(&[
        "compare",
        "--ref",
        reference.to_str().expect("utf-8"),
        img.to_str().expect("utf-8"),
        reference.to_str().expect("utf-8"),
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // Both were rendered with seed 0: they share random numbers, which is said.
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("both rendered with seed 0"), "{err}");
    let rows: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    let (noisy, exact) = (&rows[0], &rows[1]);
    for key in [
        "mse",
        "rel_mse",
        "mae",
        "mean",
        "region_error",
        "time_s",
        "efficiency",
    ] {
        assert!(noisy[key].is_number(), "{key} missing in {noisy}");
    }
    assert!(noisy["mse"].as_f64().expect("mse") > 0.0);
    assert_eq!(exact["mse"], 0.0);
    let e = noisy["efficiency"].as_f64().expect("eff");
    let expect = 1.0 / (noisy["mse"].as_f64().expect("mse") * noisy["time_s"].as_f64().expect("t"));
    assert!((e - expect).abs() <= 1e-9 * expect);
    // Another seed: no warning. Its error map goes beside it. Another scene: refused.
    assert!(render(&img, &["--seed", "5"]).status.success());
    let o = fenestra(&[
        "compare",
        "--ref",
        reference.to_str().expect("utf-8"),
        img.to_str().expect("utf-8"),
        "--error-maps",
    ]);
    assert!(o.status.success() && o.stderr.is_empty(), "{o:?}");
    let map = Image::read(&img.with_extension("error.png")).expect("map");
    assert_eq!((map.width, map.height), (24, 16));
    assert!(map.pixels.iter().any(|p| p.luminance() > 0.0));
    let cornell = tmp("cmp-cornell.exr");
    let c = fenestra(&[
        "render",
        "builtin:cornell-box",
        "--spp",
        "1",
        "--resolution",
        "24x16",
        "-o",
        cornell.to_str().expect("utf-8"),
    ]);
    assert!(c.status.success());
    assert_compare_refused(
        &reference,
        &cornell,
        "is an image of scene 'cornell-box' and the reference",
    );
}

#[test]
fn compare_downsamples_a_larger_reference_on_request() {
    let render_at = |name: &str, resolution: &str, seed: &str| {
        let out = tmp(name);
        let o = fenestra(&[
            "render",
            "builtin:box-hole",
            "--spp",
            "4",
            "--resolution",
            resolution,
            "--seed",
            seed,
            "-q",
            "-o",
            out.to_str().expect("utf-8"),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        out
    };
    let (image, reference) = (
        render_at("ds-img.exr", "24x16", "1"),
        render_at("ds-ref.exr", "72x48", "2"),
    );
    assert_compare_refused(
        &reference,
        &image,
        "is 24x16, the reference 72x48 (3 times larger): add --downsample",
    );
    let path = |p: &Path| p.to_str().expect("utf-8").to_string();
    let o = fenestra(&[
        "compare",
        "--downsample",
        "--json",
        "--ref",
        &path(&reference),
        &path(&image),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    let ref_mean = rows[0]["ref_mean"].as_f64().expect("ref_mean");
    let full = Image::read(&reference).expect("reference").mean();
    let full = f64::from(full.r + full.g + full.b) / 3.0;
    assert!(
        (ref_mean / full - 1.0).abs() < 1e-4,
        "{ref_mean} against {full}"
    );
    let odd = render_at("ds-odd.exr", "25x16", "1");
    assert_compare_refused(&reference, &odd, "not a whole multiple");
}

#[test]
fn compare_tells_apart_scenes_of_one_name_by_their_content() {
    // Two scene.pbrt files in two folders (as Bitterli's scene-v4.pbrt), one lamp brighter.
    let scene = |folder: &str, power: &str| {
        let dir = tmp(folder);
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("scene.pbrt");
        std::fs::write(
            &path,
            format!(
                "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n\
                 WorldBegin\nLightSource \"point\" \"rgb I\" [{power} {power} {power}] \
                 \"point3 from\" [0 0 3]\nShape \"trianglemesh\" \
                 \"point3 P\" [-1 -1 0 1 -1 0 1 1 0 -1 1 0] \"integer indices\" [0 1 2 0 2 3]\n"
            ),
        )
        .expect("scene");
        path
    };
    let render_of = |scene: &Path, name: &str, seed: &str| {
        let out = tmp(name);
        let o = fenestra(&[
            "render",
            scene.to_str().expect("utf-8"),
            "--spp",
            "1",
            "--resolution",
            "8x8",
            "--seed",
            seed,
            "-o",
            out.to_str().expect("utf-8"),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        out
    };
    let a = render_of(&scene("one-a", "5"), "one-a.exr", "1");
    let copy = render_of(&scene("one-b", "5"), "one-b.exr", "2");
    let other = render_of(&scene("one-c", "9"), "one-c.exr", "2");
    let o = fenestra(&[
        "compare",
        "--ref",
        a.to_str().expect("utf-8"),
        copy.to_str().expect("utf-8"),
    ]);
    assert!(
        o.status.success(),
        "a copy of the scene elsewhere is the same scene: {o:?}"
    );
    assert_compare_refused(&a, &other, "their scenes' contents differ");
}

#[test]
fn bench_writes_a_report_and_resumes() {
    let (dir, suite, args) = bench_suite(
        "bench",
        r#"name = "ci"
resolution = [8, 8]
repetitions = 2
[reference]
integrator = "af_hf"
spp = 64
[[scene]]
scene = "builtin:box-hole"
max_depth = [2]
[[technique]]
label = "HF"
integrator = "hf"
[[technique]]
label = "AF_HF"
integrator = "af_hf"
[[budget]]
spp = 8
"#,
    );
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = fenestra(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in [
        "index.html",
        "results.json",
        "table.md",
        "plots/box-hole-d2-time.svg",
        "img/box-hole-d2-af_hf-8spp-r0-err.png",
    ] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(
        table.contains("| builtin:box-hole | 2 | 8spp | AF_HF |"),
        "{table}"
    );
    let lines = |p: &Path| std::fs::read_to_string(p).expect("results").lines().count();
    assert_eq!(lines(&dir.join("results.jsonl")), 4);
    // Running again resumes: nothing is rendered twice.
    let o = fenestra(&args);
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("[1/4]"), "finished runs are skipped");
    assert!(
        err.contains("4 finished runs reused"),
        "and the reuse is said: {err}"
    );
    assert_eq!(lines(&dir.join("results.jsonl")), 4);
    let html = std::fs::read_to_string(dir.join("index.html")).expect("html");
    assert!(html.contains("<table>") && html.contains("plots/box-hole-d2-spp.svg"));
    // A technique changed under the same label is run again, not taken from the record.
    let text = std::fs::read_to_string(&suite).expect("suite");
    std::fs::write(
        &suite,
        text.replace("integrator = \"hf\"", "integrator = \"lp_hf\""),
    )
    .expect("suite");
    let o = fenestra(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    // Its runs are the first and third (the techniques alternate within a repetition).
    assert!(
        err.contains("[1/4]") && err.contains("[3/4]") && !err.contains("[2/4]"),
        "{err}"
    );
    assert_eq!(lines(&dir.join("results.jsonl")), 6);
    // Every run failing is a failure of the command, naming the runs.
    std::fs::write(
        &suite,
        text.replace("integrator = \"hf\"", "integrator = \"nope\""),
    )
    .expect("suite");
    let o = fenestra(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("2 of 4 runs failed (box-hole-d2-hf-8spp-r0"),
        "{err}"
    );
}

#[test]
fn btf_lpca_and_prt_commands_work_end_to_end() {
    let (btf, out, prt) = (tmp("btf.npy"), tmp("lpca-out"), tmp("prt.npy"));
    let s = |p: &Path| p.to_str().expect("utf-8").to_string();
    let o = fenestra(&[
        "btf",
        "--size",
        "8",
        "--views",
        "4",
        "--lights",
        "4",
        "--materials",
        "3",
        "--dim",
        "2",
        "-o",
        &s(&btf),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for algorithm in ["lpca", "sc-lpca"] {
        let dir = out.join(algorithm);
        let o = fenestra(&[
            "lpca",
            &s(&btf),
            "--clusters",
            "3",
            "--schedule",
            "0:3,2:2",
            "--algorithm",
            algorithm,
            "-o",
            &s(&dir),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        for f in [
            "assignments.npy",
            "means.npy",
            "bases.npy",
            "dims.npy",
            "coefficients.npy",
            "stats.json",
        ] {
            assert!(dir.join(f).exists(), "{f}");
        }
        let stats: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("stats.json")).expect("stats"))
                .expect("json");
        assert_eq!(
            stats["outcome"]["iterations"]
                .as_array()
                .expect("iterations")
                .len(),
            5
        );
    }
    let read = |p: PathBuf| std::fs::read(p).expect("npy");
    assert_eq!(
        read(out.join("lpca/assignments.npy")),
        read(out.join("sc-lpca/assignments.npy"))
    );
    let o = fenestra(&[
        "prt",
        "--segments",
        "8",
        "--sides",
        "4",
        "--resolution",
        "2",
        "--supersample",
        "1",
        "-o",
        &s(&prt),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("32 vertices x 24 cubemap pixels"));
    assert_clear_error(
        &["lpca", "/no/data.npy", "--clusters", "2", "-o", &s(&out)],
        "/no/data.npy",
    );
    assert_clear_error(
        &[
            "lpca",
            &s(&btf),
            "--clusters",
            "2",
            "--schedule",
            "0:x",
            "-o",
            &s(&out),
        ],
        "bad schedule entry '0:x'",
    );
    assert_clear_error(
        &["lpca", &s(&btf), "--clusters", "1000", "-o", &s(&out)],
        "--clusters must be between 1 and the number of points (64)",
    );
    assert_clear_error(
        &["prt", "--resolution", "4096", "-o", &s(&prt)],
        "would take",
    );
}

/// Where [`judged`] writes fenestra's render of `scene` with `seed`.
fn judged_image(scene: &Path, seed: u32) -> PathBuf {
    let name = scene.file_stem().and_then(|s| s.to_str()).expect("utf-8");
    let parent = scene
        .parent()
        .and_then(|p| p.file_name())
        .and_then(|s| s.to_str());
    tmp(&format!("{}-{name}-{seed}.exr", parent.unwrap_or("")))
}

/// An image's mean red, green and blue.
fn channel_means(path: &Path) -> [f64; 3] {
    let image = Image::read(path).expect("an image");
    let mut sum = [0.0f64; 3];
    for p in &image.pixels {
        for (s, c) in sum.iter_mut().zip([p.r, p.g, p.b]) {
            *s += f64::from(c);
        }
    }
    sum.map(|s| s / image.pixels.len() as f64)
}

/// fenestra's render of a pbrt-v4 scene against a reference image: (mean, reference mean,
/// relative mean error, 8x8 region error), from `fenestra compare`. No warning may be
/// printed but those `allowed` contains.
fn judged(
    scene: &Path,
    reference: &Path,
    (resolution, spp, seed): (&str, u32, u32),
    allowed: &[&str],
) -> (f64, f64, f64, f64) {
    let name = scene.file_stem().and_then(|s| s.to_str()).expect("utf-8");
    let out = judged_image(scene, seed);
    let o = fenestra(&[
        "render",
        scene.to_str().expect("utf-8"),
        "--resolution",
        resolution,
        "--spp",
        &spp.to_string(),
        "--seed",
        &seed.to_string(),
        "--variance",
        "-q",
        "-o",
        out.to_str().expect("utf-8"),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{name}: {err}");
    let warnings: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("warning") && !allowed.iter().any(|a| l.contains(a)))
        .collect();
    assert!(warnings.is_empty(), "{name}: {warnings:?}");
    let o = fenestra(&[
        "compare",
        "--json",
        "--ref",
        reference.to_str().expect("utf-8"),
        out.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    let m = &v[0];
    let (Some(mean), Some(reference)) = (m["mean"].as_f64(), m["ref_mean"].as_f64()) else {
        panic!("{name}: no means in {m}")
    };
    let region_error = m["region_error"].as_f64().unwrap_or(f64::NAN);
    (
        mean,
        reference,
        (mean / reference - 1.0).abs(),
        region_error,
    )
}

/// Two of Bitterli's interiors (CC0, tests/scenes/README.md) rendered small: they load with
/// nothing replaced but the integrator, and their image mean and 8x8 region means agree with
/// two references, each box-filtered or rendered at 64x64, within the stated tolerances:
/// Tungsten's renders (of the scenes as Bitterli wrote them) and pbrt-v4's (of these very
/// files, `scripts/pbrt-judge`'s settings: its path tracer, the scene's path length). The
/// region tolerance covers 256-spp noise; a material or light off by a few percent fails.
/// veach-bidir is lit through a glass egg and a metal lamp: one 256-spp image's mean has a
/// long tail (over 40 seeds, from -0.9% to +5.8% of the reference; a fifth beyond +2%, from
/// rare bright paths), so that scene is judged by the medians over nine seeds, which a
/// systematic error moves as much as the means.
#[test]
fn real_scenes_match_their_reference_renders() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes");
    // (scene, seeds, [(reference, mean tolerance, region tolerance)]); at 256 spp they
    // measured, against Tungsten and pbrt-v4: cornell-box 0.14% and 0.37%, and +0.8% (pbrt-v4
    // renders spectrally: its coloured walls' interreflections differ from RGB's) and 1.1%;
    // veach-bidir (lit indirectly, noisier) medians of 0.4% and 4%, and 0.4% and 3.6%.
    let tungsten = "reference-64.exr";
    let pbrt_v4 = "reference-pbrt-v4-64.exr";
    for (name, seeds, references) in [
        (
            "cornell-box",
            1,
            [(tungsten, 0.01, 0.015), (pbrt_v4, 0.015, 0.02)],
        ),
        (
            "veach-bidir",
            9,
            [(tungsten, 0.03, 0.06), (pbrt_v4, 0.03, 0.06)],
        ),
    ] {
        let dir = scenes.join(name);
        for (reference, mean_tol, region_tol) in references {
            let mut errors: Vec<(f64, f64, f64, f64)> = (0..seeds)
                .map(|seed| {
                    judged(
                        &dir.join("scene-v4.pbrt"),
                        &dir.join(reference),
                        ("64x64", 256, seed),
                        &["Integrator \"bdpt\""],
                    )
                })
                .collect();
            errors.sort_by(|a, b| a.0.total_cmp(&b.0));
            let (mean, reference_mean, mean_error, _) = errors[errors.len() / 2];
            let mut regions: Vec<f64> = errors.iter().map(|e| e.3).collect();
            regions.sort_by(f64::total_cmp);
            let region_error = regions[regions.len() / 2];
            assert!(
                mean_error < mean_tol && region_error < region_tol,
                "{name} against {reference}: median mean {mean:.4} vs {reference_mean:.4} \
                 ({:.2}%, tolerance {}%), median region error {:.2}% (tolerance {}%)",
                100.0 * mean_error,
                100.0 * mean_tol,
                100.0 * region_error,
                100.0 * region_tol
            );
        }
    }
}

/// The one-feature scenes (tests/scenes/features, written by scripts/feature-scenes: one
/// material, relief, texture, light or film setting each on a sphere and a floor) against
/// pbrt-v4's renders of them (64x48, 16384 spp in 8 seeded renders, whose spread gives the
/// reference's variance), at 1024 spp: each must be within noise of pbrt-v4, by z-tests of
/// the image's channel means and of 8x8-pixel regions (significance 1e-4 each, Sidak-corrected;
/// differences under 0.05% of a value aside), unless its difference is a documented choice
/// (`CHOSEN`), which is held to issue 47's bar instead: image mean within
/// 1%, 8x8 region error within 3%, each channel's mean within 2.5% (a colour transform can
/// keep the luminance and move the colours); a named camera sensor to its measured size.
#[test]
fn feature_scenes_render_as_pbrt_v4_renders_them() {
    // Differences that are choices, measured in docs/scenes.md ("One feature at a time"), each
    // held to a bar: image mean, 8x8 region error, worst channel mean.
    const BAR: [f64; 3] = [0.01, 0.03, 0.025];
    const CHOSEN: [(&str, &str, [f64; 3]); 7] = [
        ("texture-sphere", "colours: spectra against RGB", BAR),
        ("coated-diffuse-smooth", "colours: spectra against RGB", BAR),
        ("film-whitebalance", "colours: spectra against RGB", BAR),
        ("coated-diffuse-rough", "pbrt-v4's coat", BAR),
        ("coated-scattering", "pbrt-v4's coat", BAR),
        ("coated-conductor", "pbrt-v4's coat, colours", BAR),
        // Measured +4.1%, 5.6% and 7.4%.
        (
            "film-sensor",
            "a camera's colour response",
            [0.05, 0.065, 0.085],
        ),
    ];
    const FLOOR: f32 = 5e-4;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/features");
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("features")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "pbrt"))
        .collect();
    scenes.sort();
    assert!(scenes.len() >= 15, "{scenes:?}");
    let mut failures = Vec::new();
    for scene in &scenes {
        let name = scene.file_stem().and_then(|s| s.to_str()).expect("utf-8");
        let reference = scene.with_extension("pbrt-v4.exr");
        let (mean, reference_mean, mean_error, region_error) =
            judged(scene, &reference, ("64x48", 1024, 0), &["sensor"]);
        let ours = judged_image(scene, 0);
        let read = |p: &Path| Image::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        let (image, variance) = (read(&ours), read(&ours.with_extension("var.exr")));
        let (theirs, their_variance) = (
            read(&reference),
            read(&scene.with_extension("pbrt-v4.var.exr")),
        );
        let (a, b) = (channel_means(&ours), channel_means(&reference));
        let channel_error = (0..3)
            .map(|c| (a[c] / b[c] - 1.0).abs())
            .fold(0.0, f64::max);
        // Differences under 0.05% of a value are not tested: pbrt-v4's round trip of an RGB
        // colour through its spectra moves a plain sky seen directly by 0.03%, where both
        // images are all but noiseless. The floor is a standard error added to the
        // reference's: to a region's mean through each pixel's variance (64 pixels a region).
        let floored = {
            let mut v = their_variance.clone();
            for (v, r) in v.pixels.iter_mut().zip(&theirs.pixels) {
                *v = *v + *r * *r * (FLOOR * FLOOR * 64.0);
            }
            v
        };
        let whole = whole_image_z(&image, &variance, &theirs, &their_variance, FLOOR.into());
        let regions = fenestra_eval::z_test(&image, &variance, &theirs, Some(&floored), 1e-4, 8)
            .expect("sizes");
        let chosen = CHOSEN.iter().find(|c| c.0 == name);
        let line = format!(
            "{name}: mean {mean:.4} vs pbrt-v4 {reference_mean:.4} ({:+.2}%), region error \
             {:.2}%, worst channel mean {:.2}% off; channel means' z {:.2} {:.2} {:.2}, \
             smallest region p {:.1e} ({} of {} regions fail){}",
            100.0 * (mean / reference_mean - 1.0),
            100.0 * region_error,
            100.0 * channel_error,
            whole[0],
            whole[1],
            whole[2],
            regions.min_p,
            regions.failing,
            regions.tests,
            chosen.map_or(String::new(), |c| format!(" [a choice: {}]", c.1)),
        );
        println!("{line}");
        let failed = match chosen {
            Some(&(_, _, [mean_bar, region_bar, channel_bar])) => {
                mean_error > mean_bar || region_error > region_bar || channel_error > channel_bar
            }
            // Sidak over three channels at 1e-4: |z| beyond 4.06.
            None => whole.iter().any(|z| z.abs() > 4.06) || !regions.passed,
        };
        if failed {
            failures.push(line);
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Each channel's image-mean difference over its standard error, from both images'
/// per-pixel variances of their means and a floor, a fraction of the reference's mean.
fn whole_image_z(
    image: &Image,
    variance: &Image,
    reference: &Image,
    ref_variance: &Image,
    floor: f64,
) -> [f64; 3] {
    let sums = |im: &Image| {
        im.pixels.iter().fold([0.0f64; 3], |mut s, p| {
            for (s, v) in s.iter_mut().zip(p.to_array()) {
                *s += f64::from(v);
            }
            s
        })
    };
    let (x, v, r, rv) = (
        sums(image),
        sums(variance),
        sums(reference),
        sums(ref_variance),
    );
    let n = image.pixels.len() as f64;
    std::array::from_fn(|c| {
        let (mean, ref_mean) = (x[c] / n, r[c] / n);
        (mean - ref_mean) / ((v[c] + rv[c]) / (n * n) + (floor * ref_mean).powi(2)).sqrt()
    })
}

#[test]
fn sdrc_maps_its_cache_and_compare_measures_under_its_mask() {
    let dir = tmp("sdrc");
    std::fs::create_dir_all(&dir).expect("dir");
    let out = dir.join("t.exr");
    let render = |integrator: &str, out: &Path| {
        let o = fenestra(&[
            "render",
            "builtin:teapot-box",
            "--integrator",
            integrator,
            "--sdrc-diffuse",
            "path",
            "--spp",
            "2",
            "--resolution",
            "24x24",
            "--maps",
            "-q",
            "-o",
            out.to_str().expect("utf-8"),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    render("sdrc", &out);
    let sidecar: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("t.json")).expect("sidecar"))
            .expect("json");
    assert!(
        sidecar["extra"]["sdrc_records"].as_f64() > Some(0.0),
        "{sidecar}"
    );
    assert_eq!(sidecar["settings"]["sdrc"]["m"], 2, "{sidecar}");
    // With diffuse surfaces path traced, the cache serves the teapot only.
    let mask = dir.join("t-maps/cached.exr");
    let cached = Image::read(&mask).expect("cached map");
    let served = cached.pixels.iter().filter(|p| p.r > 0.5).count();
    assert!(
        (30..24 * 24 / 2).contains(&served),
        "{served} pixels cached"
    );
    let compare = |args: &[&str]| {
        let mut all = vec!["compare", "--ref", out.to_str().expect("utf-8"), "--json"];
        all.extend_from_slice(args);
        fenestra(&all)
    };
    let o = compare(&[
        "--mask",
        mask.to_str().expect("utf-8"),
        out.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    assert_eq!(rows[0]["mse"], 0.0);
    // The mean under the mask is the teapot's, not the image's.
    let image = Image::read(&out).expect("exr");
    let teapot: f64 = image
        .pixels
        .iter()
        .zip(&cached.pixels)
        .filter(|(_, m)| m.r > 0.5)
        .map(|(p, _)| (p.r + p.g + p.b) as f64)
        .sum::<f64>()
        / (3 * served) as f64;
    let mean = rows[0]["mean"].as_f64().expect("mean");
    assert!((mean - teapot).abs() < 1e-5 * teapot, "{mean} vs {teapot}");
    // Its caches span the whole image: it refuses to render a piece.
    for piece in [["--samples", "0..2"], ["--crop", "0,0,8,8"]] {
        let o = fenestra(&[
            "render",
            "builtin:teapot-box",
            "--integrator",
            "sdrc",
            "--resolution",
            "24x24",
            piece[0],
            piece[1],
            "-q",
            "-o",
            dir.join("piece.exr").to_str().expect("utf-8"),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            !o.status.success() && err.contains("renders whole, not in pieces"),
            "{err}"
        );
    }
    // A mask of another size is refused, naming both sizes.
    let small = dir.join("small.exr");
    let o = fenestra(&[
        "render",
        "builtin:teapot-box",
        "--spp",
        "1",
        "--resolution",
        "8x8",
        "-q",
        "-o",
        small.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success());
    let o = compare(&[
        "--mask",
        small.to_str().expect("utf-8"),
        out.to_str().expect("utf-8"),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("is 8x8, the reference 24x24"),
        "{err}"
    );
}
