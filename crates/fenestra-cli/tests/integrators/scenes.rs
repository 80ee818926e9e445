//! Scene files through the command line: export, render, what they cannot represent, environments, and pbrt-v4's rule for a surface's sides.

use super::*;

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
    let render = |scene: &str| {
        fenestra(&[
            "render",
            scene,
            "--spp",
            "1",
            "--resolution",
            "8x8",
            "-q",
            "-o",
            out,
        ])
    };
    let o = render(odd);
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

    // What render refuses, check reports: it builds the scene as render does (a glTF
    // triangle glowing beyond 32-bit floats, a point light of negative colour).
    let gltf = |extensions: &str, material: &str, lights: &str| {
        format!(
            r#"{{"asset": {{"version": "2.0"}}, "extensionsUsed": [{extensions}],
            "scene": 0, "scenes": [{{"nodes": [0, 1]}}],
            "nodes": [{{"mesh": 0}}, {{"translation": [0, 0, 2]{lights}}}],
            "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "material": 0}}]}}],
            "materials": [{{{material}}}],
            "buffers": [{{"byteLength": 36,
                "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}}],
            "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
            "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                "min": [0, 0, 0], "max": [1, 1, 0]}}]{}}}"#,
            if lights.is_empty() {
                String::new()
            } else {
                r#", "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "color": [-1, 1, 1]}]}}"#.into()
            }
        )
    };
    for (name, text, why) in [
        (
            "glowing.gltf",
            gltf(
                r#""KHR_materials_emissive_strength""#,
                r#""emissiveFactor": [1, 1, 1], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 1e39}}"#,
                "",
            ),
            "shape 0: emitted radiance",
        ),
        (
            "negative.gltf",
            gltf(
                r#""KHR_lights_punctual""#,
                "",
                r#", "extensions": {"KHR_lights_punctual": {"light": 0}}"#,
            ),
            "light 0: position or intensity is not finite, or intensity is negative",
        ),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, text).expect("write");
        let path = path.to_str().expect("utf-8");
        let o = render(path);
        let refusal = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(!o.status.success(), "{name} rendered");
        let o = fenestra(&["scene", "check", path]);
        let text = String::from_utf8_lossy(&o.stdout);
        assert_eq!(o.status.code(), Some(1), "{text}");
        let reason = text.split("\nRefused\n  ").nth(1).expect("a reason").trim();
        assert!(
            text.contains(": render refuses it") && refusal.contains(reason),
            "{text}\n{refusal}"
        );
        assert!(reason.contains(why), "{reason}");
    }

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
