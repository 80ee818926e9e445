//! Light portals from the command line: from the scene, a file, `fenestra portals` and its exports, and the cache of estimated portals.

use super::*;

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
        "invalid value 'glass' for '--deposit <DEPOSIT>'",
    );
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

/// An estimate that a render's `--time` budget cut short (photon tracing takes at most a
/// quarter of 0.5 s, where the door ajar's photons take 0.4 s) is not cached, since the
/// cache keys it by the parameters asked for and a render with more time would read it; the
/// same estimate without a budget is.
#[test]
fn an_estimate_cut_short_by_the_time_budget_is_not_cached() {
    let dir = tmp("portal-cache-budget");
    let cache = dir.join("cache");
    let render = |budget: &[&str]| {
        let out = dir.join("door.exr");
        let mut args = vec![
            "render",
            "builtin:rooms-door-ajar",
            "--integrator",
            "lp_hf",
            "--portals",
            "auto",
            "--portal-cache",
            cache.to_str().expect("utf-8"),
            "--resolution",
            "16x16",
            "-q",
            "-o",
            out.to_str().expect("utf-8"),
        ];
        args.extend(budget);
        let o = fenestra(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    let cached = || std::fs::read_dir(&cache).map_or(0, |d| d.count());
    render(&["--time", "0.5"]);
    assert_eq!(cached(), 0, "a cut-short estimate was cached");
    render(&["--spp", "1"]);
    assert_eq!(cached(), 1, "the whole estimate was not cached");
    let _ = std::fs::remove_dir_all(&dir);
}
