//! Scenes and the research integrators from the command line: scene files and their export,
//! light portals (from the scene, a file, an estimate and its cache), ias and its work maps,
//! the learned light sampler.

mod common;

use common::*;
use fenestra_core::image::Image;
use std::path::{Path, PathBuf};

#[test]
fn scene_files_export_render_and_report_what_they_cannot_represent() {
    let dir = tmp("scenes");
    std::fs::create_dir_all(&dir).expect("dir");
    // Into a folder that does not exist yet: the export creates it.
    let pbrt = dir.join("exported").join("cornell.pbrt");
    let p = pbrt.to_str().expect("utf-8");
    let o = fenestra(&["scene", "export", "builtin:cornell-box", "-o", p]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The export renders like the built-in scene, pixel for pixel.
    let (a, b) = (dir.join("a.exr"), dir.join("b.exr"));
    for (scene, out) in [("builtin:cornell-box", &a), (p, &b)] {
        let o = fenestra(&[
            "render",
            scene,
            "--strict",
            "--spp",
            "2",
            "--resolution",
            "32x32",
            "-q",
            "-o",
            out.to_str().expect("utf-8"),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let (ia, ib) = (
        fenestra_core::image::Image::read(&a).expect("a"),
        fenestra_core::image::Image::read(&b).expect("b"),
    );
    assert_eq!(ia, ib);

    let odd = dir.join("odd.pbrt");
    std::fs::write(&odd, "WorldBegin\nLightSource \"infinite\"\nShape \"curve\"\nShape \"sphere\" \"float zmin\" 0\n").expect("write");
    let odd = odd.to_str().expect("utf-8");
    let out = dir.join("odd.exr");
    let out = out.to_str().expect("utf-8");
    let o = fenestra(&[
        "render",
        odd,
        "--spp",
        "1",
        "--resolution",
        "8x8",
        "-q",
        "-o",
        out,
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("odd.pbrt:3:1: unsupported: Shape \"curve\""),
        "{err}"
    );
    assert!(
        err.contains("odd.pbrt:4:1: unsupported: partial sphere"),
        "{err}"
    );
    assert_clear_error(
        &["render", odd, "--strict", "-o", out],
        "odd.pbrt:3:1: unsupported in strict mode: Shape \"curve\"",
    );

    // `scene check` groups what is replaced and what is rendered fenestra's own way, exits 1
    // when something is replaced, and reads gzip-compressed files.
    let o = fenestra(&["scene", "check", odd]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{text}");
    let geometry = text.find("\nGeometry\n").expect("a geometry group");
    let curve = text.find("replaced  Shape \"curve\"").expect("the curve");
    assert!(geometry < curve, "{text}");
    let coated = dir.join("coated.pbrt.gz");
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(
        &mut gz,
        b"WorldBegin\nLightSource \"infinite\"\nMaterial \"coateddiffuse\" \"float roughness\" 0.1\nShape \"sphere\"\n",
    )
    .expect("gzip");
    std::fs::write(&coated, gz.finish().expect("gzip")).expect("write");
    let o = fenestra(&["scene", "check", coated.to_str().expect("utf-8")]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{text}");
    assert!(
        text.contains("nothing replaced, 1 kind of input rendered fenestra's own way")
            && text.contains("\nMaterials\n  own way   rough coats of coated materials evaluated as their own sampling gives them"),
        "{text}"
    );

    let o = fenestra(&["scene", "info", "builtin:terminal-832", "--json"]);
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    assert_eq!(v["point_lights"], 613);
    assert_eq!(v["area_lights"], 219);
    assert_eq!(v["lights"], 613 + 219);
    // Lights as light sampling counts them: a mesh's emitting triangles each.
    let o = fenestra(&["scene", "info", "builtin:tower"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("lights: 4609 (4608 area in 1 emitting shape, 0 point, 0 spot, 0 distant, 1 environment)"),
        "{text}"
    );
    assert_clear_error(
        &["scene", "export", "builtin:tunnel", "-o", "x.txt"],
        "must end in .pbrt",
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn lp_hf_takes_portals_from_the_scene_or_a_file() {
    let dir = tmp("portals");
    std::fs::create_dir_all(&dir).expect("dir");
    let out = dir.join("lp.exr");
    let o = out.to_str().expect("utf-8");
    let args = [
        "render",
        "builtin:box-hole",
        "--integrator",
        "lp_hf",
        "--spp",
        "2",
        "--resolution",
        "16x16",
        "-q",
        "-o",
        o,
    ];
    let r = fenestra(&args);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let json = dir.join("p.json");
    std::fs::write(
        &json,
        r#"{"portals":[{"kind":"ellipse","center":[0,0,0.5],"normal":[0,0,1],"area":0.05,"axes":[[0.15,0,0],[0,0.15,0]]}]}"#,
    )
    .expect("json");
    let j = json.to_str().expect("utf-8");
    let mut with_file = args.to_vec();
    with_file.extend(["--portals", j]);
    let r = fenestra(&with_file);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    std::fs::write(&json, r#"{"portals":[{"kind":"ellipse"}]}"#).expect("json");
    assert_clear_error(&with_file, "p.json: missing field");
    assert_clear_error(
        &[
            "render",
            "builtin:cornell-box",
            "--integrator",
            "lp_hf",
            "-o",
            o,
        ],
        "lp_hf needs light portals and the scene has none",
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn portals_command_writes_json_picture_and_exports_that_render_reads_back() {
    let dir = tmp("estimate");
    std::fs::create_dir_all(&dir).expect("dir");
    let (json, pbrt, obj) = (dir.join("p.json"), dir.join("p.pbrt"), dir.join("p.obj"));
    let p = |x: &Path| x.to_str().expect("utf-8").to_string();
    let r = fenestra(&[
        "portals",
        "builtin:box-4holes",
        "-o",
        &p(&json),
        "--export",
        &p(&pbrt),
        "--export",
        &p(&obj),
        "-q",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let out = String::from_utf8_lossy(&r.stdout);
    assert!(out.contains("portal 3: quad"), "{out}");
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("json")).expect("parse");
    assert_eq!(doc["portals"].as_array().map(Vec::len), Some(4));
    assert_eq!(doc["estimation"]["clusters"], 4);
    // The picture: SVG with its axes in metres and a dot per photon.
    let svg = std::fs::read_to_string(dir.join("p.svg")).expect("picture");
    for label in ["x (m)", "y (m)", "z (m)", "XY PROJECTION"] {
        assert!(svg.contains(label), "no '{label}' in the picture");
    }
    let photons = doc["estimation"]["photons"].as_u64().expect("photon count");
    assert_eq!(svg.matches("h0").count() as u64, 3 * photons);
    // Beside it, the camera's view (the box's camera does not see its ceiling); the hall's
    // camera sees its lit windows, drawn in the portals' colours over the grey geometry.
    let coloured = |png: &Path| {
        let view = image::open(png).expect("view").to_rgb8();
        assert_eq!(view.width(), 640);
        view.pixels()
            .filter(|p| p.0.iter().max().unwrap_or(&0) - p.0.iter().min().unwrap_or(&0) > 60)
            .count()
    };
    assert_eq!(coloured(&dir.join("p.png")), 0);
    let hall = dir.join("hall.json");
    let r = fenestra(&["portals", "builtin:hall-windows", "-o", &p(&hall), "-q"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let shown = coloured(&dir.join("hall.png"));
    assert!(shown > 500, "{shown} pixels show a portal");
    let obj_text = std::fs::read_to_string(&obj).expect("obj");
    assert_eq!(obj_text.matches("\nf ").count(), 4);
    // The pbrt export is invisible to light: the scene with it included renders the same.
    let pbrt_text = std::fs::read_to_string(&pbrt).expect("pbrt");
    assert_eq!(pbrt_text.matches("Material \"interface\"").count(), 4);
    let (scene, with) = (dir.join("s.pbrt"), dir.join("with.pbrt"));
    let e = fenestra(&["scene", "export", "builtin:box-4holes", "-o", &p(&scene)]);
    assert!(e.status.success(), "{}", String::from_utf8_lossy(&e.stderr));
    let text = std::fs::read_to_string(&scene).expect("scene");
    std::fs::write(&with, format!("{text}\nInclude \"p.pbrt\"\n")).expect("write");
    let pixels = |s: &Path, name: &str| {
        let o = dir.join(name);
        let r = fenestra(&[
            "render",
            &p(s),
            "--spp",
            "2",
            "--resolution",
            "16x16",
            "-q",
            "-o",
            &p(&o),
        ]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        Image::read(&o).expect("exr").pixels
    };
    assert_eq!(pixels(&scene, "a.exr"), pixels(&with, "b.exr"));
    // The estimated portals feed lp_hf, from the file or estimated on the fly.
    for portals in [p(&json), "auto".to_string()] {
        let o = dir.join("lp.exr");
        let r = fenestra(&[
            "render",
            "builtin:box-4holes",
            "--integrator",
            "lp_hf",
            "--portals",
            &portals,
            "--spp",
            "2",
            "--resolution",
            "16x16",
            "-q",
            "-o",
            &p(&o),
        ]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    }
    assert_clear_error(
        &[
            "render",
            "builtin:box-hole",
            "--portals",
            "auto",
            "-o",
            &p(&dir.join("x.exr")),
        ],
        "--portals: portals.source is not read by af_hf",
    );
    assert_clear_error(
        &["portals", "builtin:box-hole", "-o", &p(&dir.join("x.txt"))],
        "must end in .json",
    );
    assert_clear_error(
        &[
            "portals",
            "builtin:box-hole",
            "-o",
            &p(&json),
            "--plot",
            &p(&dir.join("x.png")),
        ],
        "the picture is SVG, name it .svg",
    );
    assert_clear_error(
        &[
            "portals",
            "builtin:box-hole",
            "-o",
            &p(&json),
            "--export",
            &p(&dir.join("x.stl")),
        ],
        "expected a .pbrt or .obj file",
    );
    assert_clear_error(
        &[
            "portals",
            "builtin:box-hole",
            "-o",
            &p(&json),
            "--theta",
            "95",
        ],
        "cone angle theta must lie in (0, 90) degrees",
    );
    assert_clear_error(
        &[
            "portals",
            "builtin:cornell-box",
            "-o",
            &p(&json),
            "--deposit",
            "glass",
        ],
        "unknown deposit rule 'glass'",
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn ias_refuses_a_sample_count_it_would_not_take() {
    let out = tmp("ias-spp.exr");
    let o = out.to_str().expect("utf-8");
    for integrator in ["ias", "ias_reference"] {
        assert_clear_error(
            &[
                "render",
                "builtin:kitchen-72",
                "--integrator",
                integrator,
                "--spp",
                "16",
                "--resolution",
                "16x12",
                "-o",
                o,
            ],
            "--spp 16 would not steer it; set --ias-threshold, or --time",
        );
    }
    // A path length: 2 is what ias renders (bench suites give every technique one), any
    // other is refused.
    assert_clear_error(
        &[
            "render",
            "builtin:kitchen-72",
            "--integrator",
            "ias",
            "--max-depth",
            "3",
            "--resolution",
            "16x12",
            "-o",
            o,
        ],
        "--max-depth: path.max_depth must be 2 for ias, which renders direct light only; got 3",
    );
    let two = fenestra(&[
        "render",
        "builtin:kitchen-72",
        "--integrator",
        "ias",
        "--max-depth",
        "2",
        "--resolution",
        "16x12",
        "--quiet",
        "-o",
        o,
    ]);
    assert!(
        two.status.success(),
        "{}",
        String::from_utf8_lossy(&two.stderr)
    );
    std::fs::remove_file(&out).expect("rendered");
    assert!(!out.exists());
}

#[test]
fn ias_writes_its_work_maps_on_request() {
    let dir = tmp("maps");
    std::fs::create_dir_all(&dir).expect("dir");
    let out = dir.join("k.exr");
    let o = fenestra(&[
        "render",
        "builtin:kitchen-72",
        "--integrator",
        "ias",
        "--resolution",
        "16x12",
        "--maps",
        "-q",
        "-o",
        out.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut names: Vec<String> = std::fs::read_dir(dir.join("k-maps"))
        .expect("maps folder")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "clusters.exr",
            "clusters.png",
            "passes.exr",
            "passes.png",
            "regions.exr",
            "regions.png",
            "scales.json",
            "shadow-rays.exr",
            "shadow-rays.png",
            "visible.exr",
            "visible.png"
        ]
    );
    let scales: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("k-maps/scales.json")).expect("scales"),
    )
    .expect("json");
    let passes = scales["passes"]["max"].as_f64();
    assert!(
        passes.is_some_and(|m| (1.0..=15.0).contains(&m)),
        "{scales}"
    );
    for n in names.iter().filter(|n| !n.ends_with(".json")) {
        let img = Image::read(&dir.join("k-maps").join(n)).expect("map image");
        assert_eq!((img.width, img.height), (16, 12), "{n}");
    }
    // The EXR holds the values the PNG's scale names.
    let values = Image::read(&dir.join("k-maps/passes.exr")).expect("exr");
    let top = values.pixels.iter().map(|p| p.r).fold(0.0f32, f32::max);
    assert_eq!(Some(top as f64), passes, "{scales}");
    // An integrator without maps says so and writes none.
    let plain = dir.join("plain.exr");
    let o = fenestra(&[
        "render",
        "builtin:box-hole",
        "--spp",
        "1",
        "--resolution",
        "8x8",
        "--maps",
        "-q",
        "-o",
        plain.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("af_hf makes no work maps"));
    assert!(!dir.join("plain-maps").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--portals auto` keeps its estimate in the cache, keyed by scene content and parameters:
/// the next render of the scene reads it (same portals, same image) instead of estimating;
/// a damaged cache file is estimated again and replaced.
#[test]
fn estimated_portals_are_cached_and_the_next_render_reads_them() {
    let dir = tmp("portal-cache");
    let cache = dir.join("cache");
    let s = |p: &Path| p.to_str().expect("utf-8").to_string();
    let render = |name: &str, extra: &[&str]| -> serde_json::Value {
        let out = dir.join(name);
        let mut args = vec![
            "render".to_string(),
            "builtin:box-hole".into(),
            "--integrator".into(),
            "lp_hf".into(),
            "--portals".into(),
            "auto".into(),
            "--spp".into(),
            "2".into(),
            "--resolution".into(),
            "16x16".into(),
            "--json".into(),
            "-q".into(),
            "-o".into(),
            s(&out),
        ];
        args.extend(extra.iter().map(|a| a.to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = fenestra(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice(&o.stdout).expect("--json prints JSON")
    };
    let with_cache = ["--portal-cache", cache.to_str().expect("utf-8")];
    let first = render("a.exr", &with_cache);
    assert!(first["extra"]["portal_estimation_s"].as_f64() > Some(0.0));
    assert!(first["extra"].get("portals_cached").is_none());
    let found = first["settings"]["portals"]["found"]
        .as_array()
        .expect("the portals found");
    assert_eq!(found.len(), 1, "box-hole has one opening");
    let files: Vec<PathBuf> = std::fs::read_dir(&cache)
        .expect("cache folder")
        .map(|e| e.expect("entry").path())
        .collect();
    assert_eq!(files.len(), 1, "{files:?}");
    let second = render("b.exr", &with_cache);
    assert_eq!(second["extra"]["portals_cached"], 1.0);
    assert!(second["extra"].get("portal_estimation_s").is_none());
    let pixels = |n: &str| Image::read(&dir.join(n)).expect("exr").pixels;
    assert_eq!(
        pixels("a.exr"),
        pixels("b.exr"),
        "the cached portals are the estimated ones"
    );
    std::fs::write(&files[0], "{ not json").expect("damage");
    let third = render("c.exr", &with_cache);
    assert!(third["extra"].get("portal_estimation_s").is_some());
    assert_eq!(pixels("a.exr"), pixels("c.exr"));
    let fourth = render("d.exr", &with_cache);
    assert_eq!(
        fourth["extra"]["portals_cached"], 1.0,
        "the damaged file was replaced"
    );
    let none = render("e.exr", &["--no-portal-cache"]);
    assert!(none["extra"].get("portal_estimation_s").is_some());
}

#[test]
fn learned_light_selection_renders_whole_and_refuses_what_it_cannot_do() {
    let out = tmp("learned.exr");
    let o = render(&out, &["--light-selection", "learned", "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).expect("--json prints JSON");
    let name = summary["settings"]["light_selection"]
        .as_str()
        .expect("light selection");
    assert!(name.starts_with("learned(mix 0.5"), "{name}");
    let refused = |extra: &[&str], why: &str| {
        let o = render(&tmp("refused.exr"), extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(why), "{extra:?}: {err}");
    };
    // It learns from every pixel's samples: no pieces.
    refused(
        &["--light-selection", "learned", "--crop", "0,0,8,8"],
        "renders whole, not in pieces",
    );
    refused(
        &["--light-selection", "learned", "--learned-mix", "1"],
        "--learned-mix: learned.mix must be at least 0 and below 1",
    );
    // Any number of records per cell is a size, not an overflow (the half boxes' threshold
    // is a multiple of it).
    let o = render(
        &tmp("learned-huge-cells.exr"),
        &[
            "--light-selection",
            "learned",
            "--learned-cell-records",
            "4000000000",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // sdrc has its own passes, which do not learn.
    refused(
        &["--integrator", "sdrc", "--light-selection", "learned"],
        "--light-selection: light.selection learned learns from a render's passes, which sdrc does not give it",
    );
}

#[test]
fn an_environment_map_replaces_the_scenes_environment() {
    let dir = tmp("environment");
    std::fs::create_dir_all(&dir).expect("dir");
    // 2:1 maps: one of the box's constant sky (radiance 1), one brighter towards +x and the
    // zenith.
    let map = |name: &str, radiance: &dyn Fn(usize, usize) -> f32| {
        let mut image = Image::new(32, 16);
        for y in 0..16 {
            for x in 0..32 {
                image.set(x, y, fenestra_core::Rgb::splat(radiance(x, y)));
            }
        }
        let path = dir.join(name);
        image.write_exr(&path, &Default::default()).expect("map");
        path
    };
    let uniform = map("uniform.exr", &|_, _| 1.0);
    let uneven = map("uneven.exr", &|x, y| {
        let phi = (x as f32 + 0.5) / 32.0 * std::f32::consts::TAU;
        1.0 + phi.cos().max(0.0) * 4.0 + (16 - y) as f32 * 0.1
    });
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec!["render", "builtin:box-hole-sky", "--resolution", "32x32"];
        args.extend_from_slice(&["--spp", "64", "--seed", "4", "-q", "-o"]);
        args.push(out.to_str().expect("utf-8"));
        args.extend_from_slice(extra);
        let o = fenestra(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        Image::read(&out).expect("render")
    };
    let path = |p: &Path| p.to_str().expect("utf-8").to_string();
    let (uniform, uneven) = (path(&uniform), path(&uneven));
    // The scene's own sky and a map of the same radiance: the same picture, up to noise.
    let own = render("own.exr", &[]).mean().luminance();
    let mapped = render("mapped.exr", &["--environment", &uniform])
        .mean()
        .luminance();
    assert!((mapped / own - 1.0).abs() < 0.03, "{own} {mapped}");
    // Strength scales the light and nothing else: twice the image, sample for sample.
    let one = render("one.exr", &["--environment", &uneven]);
    let two = render(
        "two.exr",
        &["--environment", &uneven, "--environment-strength", "2"],
    );
    let largest = |d: fenestra_core::Rgb| d.r.abs().max(d.g.abs()).max(d.b.abs());
    for (a, b) in one.pixels.iter().zip(&two.pixels) {
        assert!(
            largest(*b - *a * 2.0) <= 1e-5 * largest(*b).max(1.0),
            "{a:?} {b:?}"
        );
    }
    // Turning the map about the up axis changes the light through the hole; half a turn
    // and back is where it was.
    // A sky turned upside down lights the box through its hole from below: darker.
    let below = render(
        "below.exr",
        &["--environment", &uneven, "--environment-up", "-z"],
    );
    assert!(below.mean().luminance() < 0.9 * one.mean().luminance());
    let turned = render(
        "turned.exr",
        &["--environment", &uneven, "--environment-rotation", "180"],
    );
    assert_ne!(one, turned);
    let round = render(
        "round.exr",
        &["--environment", &uneven, "--environment-rotation", "-360"],
    );
    let close = one.pixels.iter().zip(&round.pixels);
    assert!(close.map(|(a, b)| largest(*a - *b)).fold(0.0, f32::max) < 1e-3);
    // What cannot be placed is refused by name.
    let mut img = Image::new(16, 16);
    img.set(0, 0, fenestra_core::Rgb::ONE);
    img.write_exr(&dir.join("square.exr"), &Default::default())
        .expect("square");
    for (flags, expect) in [
        (
            vec!["--environment", "square.exr"],
            "2:1 latitude-longitude image, this one is 16x16",
        ),
        (
            vec!["--environment", "uniform.exr", "--environment-up", "w"],
            "--environment-up: expected x, y, z",
        ),
        (
            vec![
                "--environment",
                "uniform.exr",
                "--environment-strength",
                "0",
            ],
            "strength must be positive",
        ),
        (vec!["--environment", "missing.exr"], "--environment"),
        (
            vec!["--environment-strength", "2"],
            "place --environment or --sky",
        ),
    ] {
        let flags: Vec<String> = flags
            .iter()
            .map(|f| {
                if f.ends_with(".exr") {
                    path(&dir.join(f))
                } else {
                    f.to_string()
                }
            })
            .collect();
        let out = path(&dir.join("refused.exr"));
        let mut args = vec!["render", "builtin:box-hole-sky", "-o", &out];
        args.extend(flags.iter().map(String::as_str));
        let o = fenestra(&args);
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(expect), "{err}");
    }
}

#[test]
fn a_pbrt_scene_goes_through_a_surface_where_its_shading_normal_says_so() {
    // A normal-mapped floor (tilts up to 19.5 degrees) seen from straight above, lit only by
    // an emitter under it: light reaches its top only along paths that pass through the floor
    // where a tilted shading normal puts a direction above it and the floor below.
    let dir = tmp("sides");
    std::fs::create_dir_all(&dir).expect("dir");
    let features = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/features");
    std::fs::copy(features.join("normals.png"), dir.join("normals.png")).expect("map");
    let quad = |z: f32, uv: &str| {
        format!(
            "Shape \"trianglemesh\" \"point3 P\" [ -100 -100 {z}  100 -100 {z}  100 100 {z}  \
             -100 100 {z} ] {uv} \"integer indices\" [ 0 1 2  0 2 3 ]"
        )
    };
    let scene = dir.join("under.pbrt");
    let text = format!(
        "Integrator \"path\" \"integer maxdepth\" [ 3 ]\n\
         LookAt 0 0 3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]\nWorldBegin\n\
         AttributeBegin\n  Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.8 0.8 ] \
         \"string normalmap\" \"normals.png\"\n  {}\nAttributeEnd\n\
         AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n  {}\nAttributeEnd\n",
        quad(0.0, "\"point2 uv\" [ 0 0  400 0  400 400  0 400 ]"),
        quad(-1.0, "")
    );
    std::fs::write(&scene, text).expect("scene");
    // Each render's mean and its standard error (from the per-pixel variance of the mean).
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec!["render", scene.to_str().expect("utf-8"), "--strict"];
        args.extend_from_slice(&["--resolution", "16x16", "--spp", "4096", "--variance"]);
        args.extend_from_slice(&["-q", "-o", out.to_str().expect("utf-8")]);
        args.extend_from_slice(extra);
        let o = fenestra(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let (image, variance) = (
            Image::read(&out).expect("render"),
            Image::read(&out.with_extension("var.exr")).expect("variance"),
        );
        let n = image.pixels.len() as f64;
        let var: f64 = variance.pixels.iter().map(|v| v.luminance() as f64).sum();
        (image.mean().luminance() as f64, var.sqrt() / n)
    };
    // pbrt-v4's way, the scene's default: the light under the floor shows through it, and
    // light sampling finds as much of it as BSDF sampling alone. Light samples along such
    // grazing paths end where they aim: a shadow ray parallel to the sampled direction from
    // the origin moved off the floor met the emitter's plane short of its point (-44%).
    let (through, se) = render("shading.exr", &[]);
    let (bsdf, bsdf_se) = render("hf.exr", &["--integrator", "hf"]);
    assert!(through > 1e-3, "{through}");
    let z = (through - bsdf) / se.hypot(bsdf_se);
    assert!(z.abs() < 4.0, "af_hf {through} hf {bsdf}: z {z:.2}");
    // Both normals must agree: no light leaks, not a single sample.
    assert_eq!(render("both.exr", &["--sides", "both"]).0, 0.0);
}
