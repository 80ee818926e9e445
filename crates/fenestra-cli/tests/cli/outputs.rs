//! What a render writes: its files, the same pixels for any thread count, passes within a time budget, progress, snapshots, and outputs that never replace inputs.

use super::*;

#[test]
fn render_writes_exr_png_and_sidecar() {
    let out = tmp("basic.exr");
    let o = render(&out, &["--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).expect("--json prints JSON");
    assert_eq!(summary["spp"], 4);
    assert_eq!(summary["rays"]["camera"], 24 * 16 * 4);
    let img = Image::read(&out).expect("exr");
    assert_eq!((img.width, img.height), (24, 16));
    assert!(img.mean().r > 0.0);
    let meta = read_exr_metadata(&out).expect("metadata");
    assert_eq!(
        meta.get("fenestra:integrator").map(String::as_str),
        Some("af_hf")
    );
    assert_eq!(meta.get("fenestra:spp").map(String::as_str), Some("4"));
    assert!(
        meta.contains_key("fenestra:render_time_s") && meta.contains_key("fenestra:shadow_rays")
    );
    let sidecar: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.with_extension("json")).expect("json"))
            .expect("valid");
    assert_eq!(sidecar["scene"], "box-hole");
    assert!(Image::read(&out.with_extension("png")).is_ok());
}

#[test]
fn one_and_two_threads_write_identical_images() {
    let (a, b) = (tmp("t1.exr"), tmp("t2.exr"));
    assert!(render(&a, &["--threads", "1", "--seed", "9"])
        .status
        .success());
    assert!(render(&b, &["--threads", "2", "--seed", "9"])
        .status
        .success());
    // Pixels bit for bit (the headers differ only in render time).
    assert_eq!(Image::read(&a).expect("a"), Image::read(&b).expect("b"));
    let png = |p: &Path| std::fs::read(p.with_extension("png")).expect("png");
    assert_eq!(png(&a), png(&b));
}

/// `scene export --sky` hands the sky to renderers that read equirectangular maps: its
/// sky.exr, given as --environment, renders bit for bit as --sky without its sun, and
/// sun.json places the sun where --sun puts it, with the disk's irradiance.
#[test]
fn scene_export_writes_the_sky_for_other_renderers() {
    let dir = tmp("sky-export");
    std::fs::create_dir_all(&dir).expect("dir");
    let sky = ["--sky", "--sun", "30,120", "--environment-up", "z"];
    let mut args = vec!["scene", "export", "builtin:box-hole-sky", "-o"];
    let pbrt = dir.join("b.pbrt");
    args.push(pbrt.to_str().expect("utf-8"));
    args.extend_from_slice(&sky);
    let o = fenestra(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let data = dir.join("b-data");
    let render = |out: &Path, extra: &[&str]| {
        let mut args = vec![
            "render",
            "builtin:box-hole-sky",
            "--resolution",
            "16x12",
            "--spp",
            "4",
        ];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["-q", "-o", out.to_str().expect("utf-8")]);
        let o = fenestra(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        Image::read(out).expect("image")
    };
    let map = data.join("sky.exr");
    let without_sun = render(
        &dir.join("a.exr"),
        &[&sky[..], &["--sun-strength", "0"]].concat(),
    );
    let from_map = render(
        &dir.join("b.exr"),
        &[
            "--environment",
            map.to_str().expect("utf-8"),
            "--environment-up",
            "z",
        ],
    );
    assert_eq!(without_sun, from_map);
    let sun: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data.join("sun.json")).expect("sun.json"))
            .expect("json");
    let d: Vec<f64> = (0..3)
        .map(|i| sun["sun"]["direction"][i].as_f64().expect("direction"))
        .collect();
    // 30 degrees up; azimuth 120 clockwise from north (phi = 0, +x) seen from above.
    let (el, az) = (30f64.to_radians(), 120f64.to_radians());
    let expected = [el.cos() * az.cos(), -el.cos() * az.sin(), el.sin()];
    for (a, b) in d.iter().zip(expected) {
        assert!((a - b).abs() < 1e-5, "{d:?} against {expected:?}");
    }
    let (l, e) = (&sun["sun"]["radiance"], &sun["sun"]["irradiance"]);
    let half = (sun["sun"]["angle_deg"].as_f64().expect("angle") / 2.0).to_radians();
    assert!((half.to_degrees() - 0.2666).abs() < 1e-3, "{sun}");
    for c in 0..3 {
        let (l, e) = (l[c].as_f64().expect("l"), e[c].as_f64().expect("e"));
        assert!(
            e > 0.0 && (e / (l * std::f64::consts::PI * half.sin().powi(2)) - 1.0).abs() < 1e-5
        );
    }
}

#[test]
fn time_budget_renders_whole_passes() {
    let out = tmp("timed.exr");
    let o = fenestra(&[
        "render",
        "builtin:box-4holes",
        "--time",
        "0.5",
        "--resolution",
        "16x16",
        "--json",
        "-o",
        out.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    assert!(s["spp"].as_u64().expect("spp") >= 1);
    assert_eq!(
        s["spp"], s["spp_max"],
        "every pixel has the same sample count"
    );
}

/// `--progress-lines`: lines `progress DONE TOTAL SECONDS` on stderr, what the Blender
/// add-on reads: with a sample count the total is the samples to take, with a time limit "-".
#[test]
fn progress_lines_count_the_samples_towards_their_total() {
    let out = tmp("progress.exr");
    let lines = |extra: &[&str]| {
        let mut args = vec!["render", "builtin:box-hole", "--resolution", "32x32"];
        args.extend(extra);
        args.extend(["--progress-lines", "-o", out.to_str().expect("utf-8")]);
        let o = fenestra(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        err.lines()
            .filter_map(|l| l.strip_prefix("progress "))
            .map(|l| l.split(' ').map(str::to_string).collect::<Vec<_>>())
            .collect::<Vec<_>>()
    };
    let counted = lines(&["--spp", "64"]);
    assert!(!counted.is_empty(), "no progress line");
    let total = 32 * 32 * 64;
    for l in &counted {
        assert_eq!(l.len(), 3, "{l:?}");
        let done: u64 = l[0].parse().expect("a count");
        assert_eq!(l[1], total.to_string(), "{l:?}");
        assert!(done <= total, "{l:?}");
        assert!(l[2].parse::<f64>().expect("seconds") >= 0.0);
    }
    let timed = lines(&["--time", "0.5"]);
    assert!(timed.iter().all(|l| l[1] == "-"), "{timed:?}");
    assert!(
        timed.len() >= 2,
        "at most 5 a second, and at the start: {timed:?}"
    );
}

#[test]
fn snapshots_leave_the_final_image_as_it_is() {
    let (plain, watched) = (tmp("plain.exr"), tmp("watched.exr"));
    let args = ["--seed", "5", "--variance", "--json"];
    assert!(render(&plain, &args).status.success());
    let o = render(
        &watched,
        &[&args[..], &["--snapshot-every", "1e-9"]].concat(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    // Passes of 1, 2 and 1 samples (4 in all): a snapshot after each.
    assert_eq!(s["extra"]["snapshots"].as_f64(), Some(3.0), "{s}");
    assert_eq!(s["interrupted"], false);
    assert_eq!(
        Image::read(&plain).expect("a"),
        Image::read(&watched).expect("b")
    );
    let var = |p: &Path| Image::read(&p.with_extension("var.exr")).expect("variance");
    assert_eq!(var(&plain), var(&watched));
    // ias finishes blocks whole: a snapshot after a block (3 x 2 of them here).
    let (plain, watched) = (tmp("ias-plain.exr"), tmp("ias-watched.exr"));
    let ias = |out: &Path, extra: &[&str]| {
        let mut args = vec!["render", "builtin:box-hole", "--integrator", "ias"];
        args.extend_from_slice(&["--resolution", "24x16", "--json", "-o"]);
        args.push(out.to_str().expect("utf-8"));
        args.extend_from_slice(extra);
        fenestra(&args)
    };
    assert!(ias(&plain, &[]).status.success());
    let o = ias(&watched, &["--snapshot-every", "1e-9"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    assert_eq!(s["extra"]["snapshots"].as_f64(), Some(6.0), "{s}");
    assert_eq!(
        Image::read(&plain).expect("a"),
        Image::read(&watched).expect("b")
    );
    // Over a complete render, snapshots go beside it and are gone once the render is done.
    let o = render(&watched, &["--seed", "6", "--snapshot-every", "1e-9", "-q"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("holds a complete render"));
    assert!(!watched.with_extension("interrupted.exr").exists());
    assert!(!watched.with_extension("interrupted.json").exists());
    let sidecar: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(watched.with_extension("json")).expect("json"),
    )
    .expect("valid");
    assert_eq!(
        (sidecar["seed"].as_u64(), &sidecar["interrupted"]),
        (Some(6), &false.into())
    );
    for (flags, expect) in [
        (
            &["--snapshot-every", "0"][..],
            "--snapshot-every must be a positive number",
        ),
        (
            &["--snapshot-every", "1", "--crop", "0,0,8,8"][..],
            "a piece is merged from its .film",
        ),
    ] {
        let o = render(&tmp("refused.exr"), flags);
        assert!(!o.status.success());
        assert!(
            String::from_utf8_lossy(&o.stderr).contains(expect),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

#[test]
fn an_impossibly_large_film_is_refused_before_allocating() {
    let out = tmp("huge.exr");
    let o = out.to_str().expect("utf-8");
    assert_clear_error(
        &[
            "render",
            "builtin:box-hole",
            "--resolution",
            "65536x65536",
            "-o",
            o,
        ],
        "too large",
    );
    assert_clear_error(
        &[
            "render",
            "builtin:box-hole",
            "--resolution",
            "100000x100000",
            "-o",
            o,
        ],
        "too large: at most 65536 pixels a side",
    );
}

#[test]
fn outputs_never_replace_inputs_or_each_other() {
    let dir = tmp("clobber");
    std::fs::create_dir_all(&dir).expect("dir");
    let p = |name: &str| dir.join(name).to_str().expect("utf-8").to_string();
    let o = fenestra(&[
        "scene",
        "export",
        "builtin:box-hole",
        "-o",
        &p("victim.pbrt"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let victim = std::fs::read(dir.join("victim.pbrt")).expect("scene");
    let reference = dir.join("ref.exr");
    let o = render(&reference, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let reference_bytes = std::fs::read(&reference).expect("reference");
    std::fs::write(dir.join("portals.json"), r#"{"portals":[{"kind":"quad","center":[0,0,0.5],"normal":[0,0,1],"area":0.0625,"vertices":[[-0.125,-0.125,0.5],[0.125,-0.125,0.5],[0.125,0.125,0.5],[-0.125,0.125,0.5]]}]}"#).expect("portals");
    let portals_bytes = std::fs::read(dir.join("portals.json")).expect("portals");
    // An environment map where an interrupted render (or a snapshot) of OUT would go.
    let mut sky = Image::new(8, 4);
    sky.set(0, 0, fenestra_core::Rgb::ONE);
    let sky_path = dir.join("sky.interrupted.exr");
    sky.write_exr(&sky_path, &Default::default()).expect("sky");
    let sky_bytes = std::fs::read(&sky_path).expect("sky");
    // An OBJ whose material library is named like a render's sidecar.
    std::fs::write(dir.join("lamp.json"), "newmtl lamp\nKe 5 5 5\n").expect("mtl");
    std::fs::write(
        dir.join("lamp.obj"),
        "mtllib lamp.json\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\n",
    )
    .expect("obj");
    for (args, expect) in [
        (
            vec!["render".into(), p("lamp.obj"), "-o".into(), p("lamp.exr")],
            "lamp.json (sidecar) is also the scene file this command reads",
        ),
        (
            vec![
                "render".into(),
                "builtin:box-hole-sky".into(),
                "--environment".into(),
                p("sky.interrupted.exr"),
                "--snapshot-every".into(),
                "1".into(),
                "-o".into(),
                p("sky.exr"),
            ],
            "is also the scene file this command reads",
        ),
        (
            vec![
                "portals".into(),
                p("victim.pbrt"),
                "-o".into(),
                p("v.json"),
                "--export".into(),
                p("victim.pbrt"),
            ],
            "is also the scene file this command reads",
        ),
        (
            vec![
                "portals".into(),
                "builtin:box-hole".into(),
                "-o".into(),
                p("p.json"),
                "--plot".into(),
                p("p.json"),
            ],
            "written twice, as the portals file and as the picture",
        ),
        (
            vec![
                "render".into(),
                "builtin:box-hole".into(),
                "--reference".into(),
                p("ref.exr"),
                "-o".into(),
                p("ref.exr"),
            ],
            "is also the reference this command reads",
        ),
        (
            vec![
                "scene".into(),
                "export".into(),
                p("victim.pbrt"),
                "-o".into(),
                p("victim.pbrt"),
            ],
            "is also the scene file this command reads",
        ),
        (
            vec![
                "render".into(),
                p("victim.pbrt"),
                "--integrator".into(),
                "lp_hf".into(),
                "--portals".into(),
                p("portals.json"),
                "-o".into(),
                p("portals.exr"),
            ],
            "is also the portals file this command reads",
        ),
    ] {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        assert_clear_error(&args, expect);
    }
    assert_eq!(
        std::fs::read(dir.join("victim.pbrt")).expect("scene"),
        victim
    );
    assert_eq!(
        std::fs::read(&reference).expect("reference"),
        reference_bytes
    );
    assert_eq!(
        std::fs::read(dir.join("portals.json")).expect("portals"),
        portals_bytes
    );
    assert_eq!(std::fs::read(&sky_path).expect("sky"), sky_bytes);
    assert_eq!(
        std::fs::read(dir.join("lamp.json")).expect("mtl"),
        b"newmtl lamp\nKe 5 5 5\n"
    );
    assert!(!dir.join("v.json").exists() && !dir.join("p.json").exists());

    // A folder in the way of the PNG is found before rendering; the old image set stays.
    std::fs::create_dir_all(dir.join("blocked.png")).expect("dir");
    let blocked = dir.join("blocked.exr");
    std::fs::write(&blocked, b"old").expect("old");
    let o = fenestra(&[
        "render",
        "builtin:box-hole",
        "--spp",
        "100000",
        "-o",
        &p("blocked.exr"),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("blocked.png: it is a folder"),
        "{err}"
    );
    assert_eq!(std::fs::read(&blocked).expect("old"), b"old");
    let leftovers = std::fs::read_dir(&dir)
        .expect("dir")
        .filter(|e| {
            e.as_ref()
                .is_ok_and(|e| e.file_name().to_string_lossy().contains(".tmp."))
        })
        .count();
    assert_eq!(leftovers, 0, "no temporary files left");
}

/// A render with light paths says what they carried: their own image beside the variance
/// image (its variance a layer), their shares of the light and the variance in the sidecar
/// and along the convergence curve; a later render without light paths leaves no stale
/// image of theirs beside its own.
#[test]
fn light_paths_show_what_they_carried() {
    let window = tmp("lp-window.json");
    let o = fenestra(
        &[
            "portals",
            "builtin:glossy-room",
            "--time",
            "0",
            "--quiet",
            "-o",
        ]
        .iter()
        .copied()
        .chain([window.to_str().expect("utf-8")])
        .collect::<Vec<_>>(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (reference, out) = (tmp("lp-ref.exr"), tmp("lp.exr"));
    let run = |out: &Path, extra: &[&str]| {
        let mut args = vec![
            "render",
            "builtin:glossy-room",
            "--resolution",
            "32x18",
            "--quiet",
        ];
        args.extend_from_slice(extra);
        args.extend(["-o", out.to_str().expect("utf-8")]);
        let o = fenestra(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    run(&reference, &["--spp", "16", "--seed", "3"]);
    let lp_lt = [
        "--integrator",
        "lp_lt",
        "--portals",
        window.to_str().expect("utf-8"),
        "--light-paths-trial",
        "0",
        "--spp",
        "8",
        "--variance",
        "--reference",
        reference.to_str().expect("utf-8"),
    ];
    run(&out, &lp_lt);
    let light = out.with_extension("light-paths.exr");
    let brought = Image::read(&light).expect("the light paths' image");
    assert!(brought.mean().luminance() > 0.0);
    let variance = fenestra_core::image::read_exr_layer(&light, "variance", ["R", "G", "B"])
        .expect("their variance");
    assert_eq!((variance.width, variance.height), (32, 18));
    assert!(light.with_extension("png").exists());
    let sidecar: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.with_extension("json")).expect("json"))
            .expect("valid");
    for share in ["light_path_share", "light_path_variance_share"] {
        let v = sidecar["extra"][share].as_f64().expect(share);
        assert!(v > 0.0 && v < 1.0, "{share}: {v}");
        let last = &sidecar["convergence"]
            .as_array()
            .expect("a curve")
            .last()
            .cloned();
        let along = last.as_ref().and_then(|p| p[share].as_f64()).expect(share);
        assert!(
            (along - v).abs() < 1e-9,
            "{share}: {along} along the curve, {v} at the end"
        );
    }
    run(&out, &["--spp", "2", "--variance"]);
    assert!(!light.exists() && !light.with_extension("png").exists());
}
