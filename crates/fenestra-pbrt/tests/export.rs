//! The pbrt-v4 exporter against the reader: every built-in scene written and read back.

use fenestra_core::{Vec2, Vec3};
use fenestra_scene::light::{EnvironmentDesc, LightDesc};
use fenestra_scene::material;
use fenestra_scene::{Material, Shape, ShapeKind};

/// Exports every built-in scene to pbrt-v4 and reads it back: the same shapes, materials,
/// lights, camera rays and settings.
#[test]
fn pbrt_export_round_trips() {
    let dir = std::env::temp_dir().join(format!("fenestra-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    for (name, _) in fenestra_builtin::SCENES {
        let mut a = fenestra_builtin::load(name).expect(name);
        // A film white balance, which no built-in scene has, goes along too.
        a.camera.white_balance = Some(4200.0);
        let path = dir.join(format!("{name}.pbrt"));
        fenestra_pbrt::export::write(&a, &path).expect("export");
        let b = fenestra_pbrt::load(&path, true).expect("re-read").desc;
        assert_eq!(a.shapes.len(), b.shapes.len(), "{name}");
        for (i, (s, t)) in a.shapes.iter().zip(&b.shapes).enumerate() {
            assert!(same_shape(s, t, 1e-5), "{name}: shape {i} differs");
        }
        // Read back as a pbrt-v4 scene, whose paths go on through surfaces as pbrt-v4's do.
        let mut expected = a.defaults.clone();
        (expected.options).insert(0, ("path.sides".into(), "shading".into()));
        assert_eq!(
            format!("{expected:?}"),
            format!("{:?}", b.defaults),
            "{name}"
        );
        assert_eq!(a.portals.len(), b.portals.len(), "{name}: portals");
        // The same quad, perhaps wound the other way (an environment's portal faces the
        // camera for pbrt-v4).
        for (p, q) in a.portals.iter().zip(&b.portals) {
            let reversed = [q[0], q[3], q[2], q[1]];
            let same = |q: &[fenestra_core::Vec3; 4]| {
                p.iter().zip(q).all(|(x, y)| (*x - *y).length() < 1e-5)
            };
            assert!(
                same(q) || same(&reversed),
                "{name}: portal {p:?} read back as {q:?}"
            );
        }
        assert_eq!(a.materials.len(), b.materials.len(), "{name}");
        for (m, n) in a.materials.iter().zip(&b.materials) {
            assert_eq!(material_key(m), material_key(n), "{name}");
        }
        assert_eq!(a.lights.len(), b.lights.len(), "{name}");
        for (l, m) in a.lights.iter().zip(&b.lights) {
            assert_eq!(light_key(l), light_key(m), "{name}");
        }
        let (w, h) = (a.defaults.width, a.defaults.height);
        for (x, y) in [
            (0.0, 0.0),
            (w as f32, h as f32),
            (w as f32 * 0.3, h as f32 * 0.8),
        ] {
            let (r, s) = (
                a.camera.generate_ray(Vec2::new(x, y), w, h),
                b.camera.generate_ray(Vec2::new(x, y), w, h),
            );
            assert!(
                (r.o - s.o).length() < 1e-4 && (r.d - s.d).length() < 1e-5,
                "{name}: camera"
            );
        }
        // The pixel filter too (pbrt-v4's default differs from fenestra's).
        assert_eq!(a.camera.filter, b.camera.filter, "{name}: pixel filter");
        assert_eq!(a.camera.white_balance, b.camera.white_balance, "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A material's kind and parameters rounded to 5 significant digits.
fn material_key(m: &Material) -> String {
    let s = match m {
        Material::TexturedDiffuse(material::TexturedDiffuse { texture }) => {
            format!("tex {:?}", texture.average())
        }
        Material::CoatedDiffuse(material::CoatedDiffuse {
            reflectance,
            eta,
            alpha,
            ..
        }) => format!("coated {reflectance:?} {eta} {alpha}"),
        other => format!("{other:?}"),
    };
    round_numbers(&s)
}

fn light_key(l: &LightDesc) -> String {
    match l {
        LightDesc::Environment(EnvironmentDesc::Image {
            image,
            scale,
            to_world,
        }) => {
            // Written as pbrt-v4's equal-area square and read back as latitude-longitude: the
            // same size, the mean to three figures (resampled twice).
            let m = image
                .mean()
                .map(|v| format!("{v:.2e}").parse().unwrap_or(v));
            round_numbers(&format!(
                "image {}x{} {m:?} {scale:?} {to_world:?}",
                image.width, image.height
            ))
        }
        other => round_numbers(&format!("{other:?}")),
    }
}

fn round_numbers(s: &str) -> String {
    let mut out = String::new();
    let mut num = String::new();
    let flush = |num: &mut String, out: &mut String| {
        if let Ok(v) = num.parse::<f64>() {
            out.push_str(&format!("{v:.4e}"));
        } else {
            out.push_str(num);
        }
        num.clear();
    };
    for c in s.chars() {
        if c.is_ascii_digit() || c == '.' || c == '-' || c == 'e' && !num.is_empty() {
            num.push(c);
        } else {
            flush(&mut num, &mut out);
            out.push(c);
        }
    }
    flush(&mut num, &mut out);
    out
}

/// Shapes compared for the round-trip test: kind, material, emission, orientation and a
/// sphere's turn.
fn same_shape(a: &Shape, b: &Shape, tol: f32) -> bool {
    let close = |x: Vec3, y: Vec3| (x - y).length() <= tol * (1.0 + x.length());
    let geometry = match (&a.kind, &b.kind) {
        (ShapeKind::Mesh(m), ShapeKind::Mesh(n)) => {
            m.indices == n.indices
                && m.positions.len() == n.positions.len()
                && m.positions
                    .iter()
                    .zip(&n.positions)
                    .all(|(x, y)| close(*x, *y))
                && m.uvs.is_some() == n.uvs.is_some()
                && m.normals.is_some() == n.normals.is_some()
        }
        (
            ShapeKind::Sphere { center, radius },
            ShapeKind::Sphere {
                center: c2,
                radius: r2,
            },
        ) => close(*center, *c2) && (radius - r2).abs() <= tol * radius,
        (
            ShapeKind::Disk {
                center,
                normal,
                radius,
            },
            ShapeKind::Disk {
                center: c2,
                normal: n2,
                radius: r2,
            },
        ) => close(*center, *c2) && close(*normal, *n2) && (radius - r2).abs() <= tol * radius,
        _ => false,
    };
    let turn = match (a.orientation, b.orientation) {
        (None, None) => true,
        (Some(x), Some(y)) => x.abs_diff_eq(y, tol),
        _ => false,
    };
    geometry
        && turn
        && a.material == b.material
        && a.flip_normals == b.flip_normals
        && a.emission.map(|e| (e.radiance, e.two_sided))
            == b.emission.map(|e| (e.radiance, e.two_sided))
}

/// Turned spheres keep their turn (their uv's object space) and their side through an
/// export, a mirroring turn too.
#[test]
fn turned_spheres_round_trip() {
    let dir = std::env::temp_dir().join(format!("fenestra-export-turned-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    std::fs::write(
        dir.join("s.pbrt"),
        r#"WorldBegin
        AttributeBegin Translate 1 2 3 Rotate 90 0 1 0 Rotate 30 1 0 0 Shape "sphere" AttributeEnd
        AttributeBegin Scale -2 2 2 Rotate 45 0 0 1 Shape "sphere" AttributeEnd
        AttributeBegin ReverseOrientation Rotate 10 1 1 0 Shape "sphere" "float radius" 0.5 AttributeEnd"#,
    )
    .expect("scene");
    let a = fenestra_pbrt::load(&dir.join("s.pbrt"), true)
        .expect("read")
        .desc;
    assert!(a.shapes.iter().all(|s| s.orientation.is_some()));
    assert!(
        a.shapes[1].flip_normals,
        "the mirrored sphere is turned inside out"
    );
    let path = dir.join("out.pbrt");
    fenestra_pbrt::export::write(&a, &path).expect("export");
    let b = fenestra_pbrt::load(&path, true).expect("re-read").desc;
    assert_eq!(a.shapes.len(), b.shapes.len());
    for (s, t) in a.shapes.iter().zip(&b.shapes) {
        assert!(same_shape(s, t, 1e-5), "{s:?}\n{t:?}");
    }
}

/// Bump and normal maps survive an export: each shape reads back with the same kind of
/// relief, the same texels and the same texture parameters, on a material of its own.
#[test]
fn bump_and_normal_maps_round_trip() {
    let dir = std::env::temp_dir().join(format!("fenestra-export-relief-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let mut img = fenestra_core::image::Image::new(3, 2);
    for (i, (x, y)) in [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1)]
        .into_iter()
        .enumerate()
    {
        img.set(x, y, fenestra_core::Rgb::new(0.1 * i as f32, 0.5, 0.9));
    }
    img.write_exr(&dir.join("t.exr"), &Default::default())
        .expect("texture");
    std::fs::write(
        dir.join("s.pbrt"),
        r#"WorldBegin
        Texture "h" "float" "imagemap" "string filename" "t.exr" "float scale" 0.2 "float uscale" 3
        Material "diffuse" "texture displacement" "h"
        Shape "sphere"
        Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "point2 uv" [0 0 1 0 0 1] "integer indices" [0 1 2]
        Material "conductor" "string normalmap" "t.exr"
        Shape "trianglemesh" "point3 P" [0 0 1 1 0 1 0 1 1] "point2 uv" [0 0 1 0 0 1] "integer indices" [0 1 2]
        Material "diffuse"
        Shape "sphere""#,
    )
    .expect("scene");
    let a = fenestra_pbrt::load(&dir.join("s.pbrt"), true)
        .expect("read")
        .desc;
    let path = dir.join("out.pbrt");
    fenestra_pbrt::export::write(&a, &path).expect("export");
    let b = fenestra_pbrt::load(&path, true).expect("re-read").desc;
    assert_eq!(a.shapes.len(), b.shapes.len());
    let lookups = |r: &material::Relief| -> Vec<String> {
        let t = match r {
            material::Relief::Bump(b) => &b.displacement,
            material::Relief::Normals(n) => &n.texture,
        };
        [
            Vec2::new(0.1, 0.2),
            Vec2::new(0.7, 0.9),
            Vec2::new(0.45, 0.5),
        ]
        .iter()
        .map(|&uv| format!("{:?}", t.lookup(uv)))
        .collect()
    };
    for (i, (s, t)) in a.shapes.iter().zip(&b.shapes).enumerate() {
        match (s.relief.as_deref(), t.relief.as_deref()) {
            (None, None) => {}
            (Some(r), Some(q)) => {
                assert_eq!(
                    std::mem::discriminant(r),
                    std::mem::discriminant(q),
                    "shape {i}"
                );
                assert_eq!(lookups(r), lookups(q), "shape {i}");
            }
            other => panic!("shape {i}: {other:?}"),
        }
        assert_eq!(
            material_key(&a.materials[s.material]),
            material_key(&b.materials[t.material]),
            "shape {i}"
        );
    }
    assert_eq!(a.shapes.iter().filter(|s| s.relief.is_some()).count(), 3);
    let _ = std::fs::remove_dir_all(&dir);
}
