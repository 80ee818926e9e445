//! The measuring commands: cached references, `compare`, bench suites with their reports and resumption, the matrix tools, and sdrc's work maps measured under a mask.

use super::*;

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

/// A technique that denoises (`--denoise` among its arguments) is scored by its denoised
/// image: from the same samples as the raw technique's, it is the closer to the reference by
/// relative MSE.
#[test]
fn bench_scores_a_denoised_run_by_its_denoised_image() {
    let (dir, _, args) = bench_suite(
        "bench-denoised",
        r#"name = "denoised"
resolution = [32, 32]
repetitions = 1
[reference]
integrator = "af_hf"
spp = 512
[[scene]]
scene = "builtin:cornell-box"
max_depth = [4]
[[technique]]
label = "RAW"
integrator = "af_hf"
[[technique]]
label = "DENOISED"
integrator = "af_hf"
args = ["--denoise"]
[[budget]]
spp = 4
"#,
    );
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = fenestra(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let results = std::fs::read_to_string(dir.join("results.jsonl")).expect("results");
    let records: Vec<serde_json::Value> = results
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON"))
        .collect();
    let by = |label: &str| {
        records
            .iter()
            .find(|r| r["spec"]["id"].as_str().expect("id").contains(label))
            .unwrap_or_else(|| panic!("{label}: {records:?}"))
    };
    let (raw, denoised) = (by("-raw-"), by("-denoised-"));
    let image = |r: &serde_json::Value| r["image"].as_str().expect("image").to_string();
    assert!(
        image(denoised).ends_with(".denoised.exr"),
        "{}",
        image(denoised)
    );
    assert!(image(raw).ends_with(".exr") && !image(raw).contains("denoised"));
    // By relative MSE (the lamp's few bright pixels, blurred at their edges, weigh most in
    // the absolute one at 32x32).
    let rel_mse = |r: &serde_json::Value| r["metrics"]["rel_mse"].as_f64().expect("rel_mse");
    assert!(
        rel_mse(denoised) < 0.5 * rel_mse(raw),
        "denoised {} against raw {}",
        rel_mse(denoised),
        rel_mse(raw)
    );
}
