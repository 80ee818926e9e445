//! pbrt-v4 input: orientation, transforms, instancing, includes, compressed files, shapes
//! (subdivision, bilinear patches, interfaces, motion blur), warnings and errors on
//! malformed files.

mod common;

use common::*;
use fenestra_core::{Rgb, Vec2, Vec3};
use fenestra_pbrt as pbrt;
use fenestra_scene::material;
use fenestra_scene::{Backend, Material, Scene, ShapeKind};
use std::path::{Path, PathBuf};

#[test]
fn left_handed_screen_space_matches_pbrt() {
    // pbrt-v4 with LookAt 0 0 -5 -> origin, up +y: camera x = up x dir = +x is image right,
    // so the sphere at world +x is on the right and the one at +y at the top. A right-handed
    // reading (x = dir x up) would mirror the picture.
    let s = load(
        r#"LookAt 0 0 -5  0 0 0  0 1 0
        Camera "perspective" "float fov" [ 60 ]
        Film "rgb" "integer xresolution" [ 200 ] "integer yresolution" [ 100 ]
        WorldBegin
        AttributeBegin Translate 1.5 0 0  Shape "sphere" "float radius" 0.5 AttributeEnd
        AttributeBegin Translate 0 1.2 0  Shape "sphere" "float radius" 0.3 AttributeEnd"#,
    )
    .expect("load");
    let scene = Scene::build(s.desc, Backend::Obvhs).expect("build");
    // The sphere centres subtend tan = 0.3 (x) and 0.24 (y); the film spans +-t vertically and
    // +-2t horizontally (aspect 2) with t = tan(30 deg).
    let t = 30f32.to_radians().tan();
    let right = shape_at(&scene, 0.5 + 0.3 / (2.0 * 2.0 * t), 0.5);
    assert_eq!(right, Some(0), "the +x sphere must be on the right");
    assert_eq!(shape_at(&scene, 0.2, 0.5), None, "nothing on the left");
    let top = 0.5 - 0.24 / (2.0 * t);
    assert_eq!(
        shape_at(&scene, 0.5, top),
        Some(1),
        "the +y sphere must be at the top"
    );
    // pbrt's fov spans the shorter (vertical) axis here: the +y sphere's top is in view.
    assert_eq!(shape_at(&scene, 0.5, 0.01), None);
}

#[test]
fn scale_minus_one_mirrors_like_pbrt() {
    let s = load(
        r#"Scale -1 1 1 LookAt 0 0 -5  0 0 0  0 1 0
        Camera "perspective" "float fov" [ 60 ]
        WorldBegin
        AttributeBegin Translate 1.5 0 0  Shape "sphere" "float radius" 0.5 AttributeEnd"#,
    )
    .expect("load");
    let scene = Scene::build(s.desc, Backend::Obvhs).expect("build");
    let (w, h) = (scene.defaults.width as f32, scene.defaults.height as f32);
    let t = 30f32.to_radians().tan();
    let x = 0.5 - 0.3 / (2.0 * t * w / h);
    assert_eq!(shape_at(&scene, x, 0.5), Some(0), "mirrored to the left");
}

#[test]
fn transforms_attributes_and_coordinate_systems() {
    let s = load(
        r#"WorldBegin
        CoordinateSystem "origin"
        AttributeBegin
          Translate 1 0 0 Rotate 90 0 0 1 Scale 2 2 2
          Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2]
        AttributeEnd
        TransformBegin Translate 5 5 5 TransformEnd
        Translate 0 0 7
        CoordSysTransform "origin"
        ConcatTransform [1 0 0 0  0 1 0 0  0 0 1 0  0 0 3 1]
        Shape "sphere" "float radius" 0.25
        Transform [1 0 0 0  0 1 0 0  0 0 1 0  9 0 0 1]
        Shape "disk" "float radius" 2 "float height" 1"#,
    )
    .expect("load");
    let shapes = &s.desc.shapes;
    let ShapeKind::Mesh(m) = &shapes[0].kind else {
        panic!("mesh")
    };
    // p' = T(1,0,0) R_z(90) S(2) p: (1,0,0) -> (2,0,0) -> (0,2,0) -> (1,2,0).
    assert!(
        (m.positions[1] - Vec3::new(1.0, 2.0, 0.0)).length() < 1e-5,
        "{:?}",
        m.positions
    );
    assert!(
        matches!(shapes[1].kind, ShapeKind::Sphere { center, .. } if (center - Vec3::new(0.0, 0.0, 3.0)).length() < 1e-6)
    );
    assert!(
        matches!(shapes[2].kind, ShapeKind::Disk { center, normal, radius } if (center - Vec3::new(9.0, 0.0, 1.0)).length() < 1e-6 && normal == Vec3::Z && radius == 2.0)
    );
}

#[test]
fn instances_includes_and_named_materials() {
    let dir = scratch("include");
    std::fs::create_dir_all(dir.join("sub")).expect("sub");
    std::fs::write(
        dir.join("sub/geometry.pbrt"),
        "ObjectBegin \"tri\"\n NamedMaterial \"red\"\n Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\nObjectEnd\n",
    )
    .expect("include");
    std::fs::write(
        dir.join("main.pbrt"),
        "WorldBegin\nMakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.8 0.1 0.1]\n\
         Include \"sub/geometry.pbrt\"\nObjectInstance \"tri\"\nTranslate 0 0 2\nObjectInstance \"tri\"\n",
    )
    .expect("main");
    let s = pbrt::load(&dir.join("main.pbrt"), true).expect("load");
    assert_eq!(s.desc.shapes.len(), 2);
    let ShapeKind::Mesh(m) = &s.desc.shapes[1].kind else {
        panic!("mesh")
    };
    assert_eq!(m.positions[0], Vec3::new(0.0, 0.0, 2.0));
    let mat = &s.desc.materials[s.desc.shapes[1].material];
    assert!(
        matches!(mat, Material::Diffuse(material::Diffuse { reflectance }) if *reflectance == Rgb::new(0.8, 0.1, 0.1))
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gzip_compressed_scene_files_and_meshes_are_read() {
    use std::io::Write;
    let gzip = |path: PathBuf, bytes: &[u8]| {
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(bytes).expect("gzip");
        std::fs::write(path, gz.finish().expect("gzip")).expect("write");
    };
    let dir = scratch("gzip");
    gzip(
        dir.join("tri.ply.gz"),
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
          property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
          end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    );
    gzip(
        dir.join("geometry.pbrt.gz"),
        b"Shape \"plymesh\" \"string filename\" \"tri.ply.gz\"\n",
    );
    gzip(
        dir.join("main.pbrt.gz"),
        b"WorldBegin\nInclude \"geometry.pbrt.gz\"\nTranslate 0 0 2\nInclude \"geometry.pbrt.gz\"\n",
    );
    let s = pbrt::load(&dir.join("main.pbrt.gz"), true).expect("load");
    assert_eq!(s.desc.shapes.len(), 2);
    let ShapeKind::Mesh(m) = &s.desc.shapes[1].kind else {
        panic!("mesh")
    };
    assert_eq!(m.positions[1], Vec3::new(1.0, 0.0, 2.0));
    // A damaged file says that it is gzip and where it was included.
    std::fs::write(dir.join("geometry.pbrt.gz"), [0x1f, 0x8b, 8, 0]).expect("damage");
    let e = pbrt::load(&dir.join("main.pbrt.gz"), true)
        .err()
        .expect("damaged")
        .to_string();
    assert!(
        e.contains("main.pbrt.gz:2:1: cannot read included file") && e.contains("gzip-compressed"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unsupported_input_is_counted_and_strict_refuses_it() {
    let text = r#"WorldBegin
    Shape "curve" "point3 P" [0 0 0 1 1 1 2 2 2 3 3 3]
    Shape "curve" "point3 P" [0 0 0 1 1 1 2 2 2 3 3 3]
    Shape "curve" "point3 P" [0 0 0 1 1 1 2 2 2 3 3 3]
    Shape "sphere" "float radius" 1 "texture alpha" "cutout"
    Material "hair""#;
    let s = load(text).expect("load");
    let w: Vec<String> = s.warnings.iter().map(ToString::to_string).collect();
    assert_eq!(w.len(), 3, "{w:?}");
    assert!(
        w[0].starts_with("test.pbrt:2:5: unsupported: Shape \"curve\" (skipped) (3 times)"),
        "{w:?}"
    );
    assert!(
        w[1].contains(
            "5:37: unsupported: parameter \"texture alpha\" of Shape \"sphere\" (ignored)"
        ),
        "{w:?}"
    );
    assert!(w[2].contains("Material \"hair\""), "{w:?}");
    let e = pbrt::load_bytes(text.as_bytes(), Path::new("test.pbrt"), true)
        .err()
        .expect("strict")
        .to_string();
    assert!(
        e.starts_with("test.pbrt:2:5: unsupported in strict mode: Shape \"curve\""),
        "{e}"
    );
    assert!(e.contains("2 more kinds"), "{e}");
}

#[test]
fn malformed_input_names_file_line_and_column() {
    let dir = scratch("bad");
    let cases: &[(&str, &[u8], &str)] = &[
        ("unterminated.pbrt", b"WorldBegin\nShape \"sphere", "unterminated.pbrt:2:7: unterminated string"),
        ("type.pbrt", b"Camera \"perspective\" \"float fov\" [ \"wide\" ]", "type.pbrt:1:22: parameter \"fov\" of type float expects numbers, found strings"),
        ("include.pbrt", b"WorldBegin\n  Include \"missing.pbrt\"", "include.pbrt:2:3: cannot read included file"),
        ("index.pbrt", b"Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n  \"integer indices\" [0 1 3]", "index.pbrt:2:3: trianglemesh index 3 is out of range (3 vertices)"),
        ("nan.pbrt", b"Translate 0 nan 0", "nan.pbrt:1:13: expected 3 numbers after Translate, found 'nan'"),
        ("inf.pbrt", b"Scale 1 1e999 1", "inf.pbrt:1:9: '1e999' is not a finite number"),
        ("empty.pbrt", b"# nothing here\n", "empty.pbrt:1:1: the scene file has no directives"),
        ("garbage.pbrt", b"Shape \x00\xff\xfe\x01", "garbage.pbrt:1:8: not a text file: invalid UTF-8 byte 0xff"),
        ("unknown.pbrt", b"WorldBegin\nSphere 1", "unknown.pbrt:2:1: unknown directive 'Sphere'"),
        ("end.pbrt", b"AttributeEnd", "end.pbrt:1:1: AttributeEnd without a matching begin"),
        ("open.pbrt", b"WorldBegin\nAttributeBegin\nShape \"sphere\"", "open.pbrt:2:1: this begin has no matching"),
        ("named.pbrt", b"NamedMaterial \"gold\"", "named.pbrt:1:1: unknown named material \"gold\""),
        ("ply.pbrt", b"Shape \"plymesh\" \"string filename\" \"nope.ply\"", "ply.pbrt:1:1: "),
        ("singular.pbrt", b"Scale 1 0 1\nShape \"sphere\"", "singular.pbrt:2:1: the current transform is singular"),
        ("lookat.pbrt", b"LookAt 0 0 0  0 0 1  0 0 1", "lookat.pbrt:1:1: LookAt: the eye equals the target, or the up vector is parallel"),
        ("radius.pbrt", b"Shape \"sphere\" \"float radius\" -1", "radius.pbrt:1:1: sphere radius must be positive"),
        ("cycle.pbrt", b"Include \"cycle.pbrt\"", "nests more than 32 files deep"),
        ("device.pbrt", b"Include \"/dev/zero\"", "device.pbrt:1:1: cannot read included file /dev/zero: not a regular file"),
        ("rgb.pbrt", b"Material \"diffuse\" \"rgb reflectance\" [0.5 0.5]", "rgb.pbrt:1:20: parameter \"reflectance\" of type rgb needs a multiple of 3 numbers, found 2"),
    ];
    for (name, text, want) in cases {
        let path = dir.join(name);
        std::fs::write(&path, text).expect("write");
        let e = match pbrt::load(&path, false) {
            Ok(_) => panic!("{name} loaded"),
            Err(e) => e.to_string(),
        };
        let shown = e.replace(&format!("{}/", dir.display()), "");
        assert!(shown.contains(want), "{name}: got '{shown}', want '{want}'");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn loop_subdivision_surfaces_are_built_as_pbrt_v4_levels_them() {
    // The killeroo scenes' bodies; they used to be skipped.
    let tetrahedron = r#""point3 P" [1 1 1  1 -1 -1  -1 1 -1  -1 -1 1]
        "integer indices" [0 1 2  0 3 1  0 2 3  1 3 2]"#;
    let s = load(&format!(
        "WorldBegin\nShape \"loopsubdiv\" \"integer levels\" 2 {tetrahedron}\n\
         Shape \"loopsubdiv\" {tetrahedron}"
    ))
    .expect("load");
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let triangles: Vec<usize> = s
        .desc
        .shapes
        .iter()
        .map(|shape| match &shape.kind {
            ShapeKind::Mesh(m) => {
                assert!(m.normals.is_some(), "smooth shading normals");
                m.indices.len()
            }
            _ => panic!("mesh"),
        })
        .collect();
    // Four times the triangles per level; pbrt-v4's default is 3 levels.
    assert_eq!(triangles, [4 * 16, 4 * 64]);
    for (levels, says) in [
        ("-1", "\"levels\" must be 0 to 8, found -1"),
        ("9", "\"levels\" must be 0 to 8, found 9"),
    ] {
        let e = load(&format!(
            "WorldBegin\nShape \"loopsubdiv\" \"integer levels\" {levels} {tetrahedron}"
        ))
        .err()
        .expect("refused");
        assert!(e.contains(says), "{e}");
    }
}

#[test]
fn bilinear_patches_become_triangles() {
    let s = load(
        r#"WorldBegin
        Shape "bilinearmesh" "point3 P" [0 0 0  2 0 0  0 1 0  2 1 0] "point2 uv" [0 0 1 0 0 1 1 1]
        Shape "bilinearmesh" "point3 P" [0 0 0  1 0 0  0 1 0  1 1 1]"#,
    )
    .expect("load");
    let ShapeKind::Mesh(flat) = &s.desc.shapes[0].kind else {
        panic!("mesh")
    };
    assert_eq!(flat.indices.len(), 2, "a planar patch is two triangles");
    assert!(((0..2).map(|t| flat.triangle_area(t)).sum::<f32>() - 2.0).abs() < 1e-6);
    let uvs = flat.uvs.as_ref().expect("uv");
    assert_eq!(uvs[3], Vec2::new(1.0, 1.0));
    let ShapeKind::Mesh(curved) = &s.desc.shapes[1].kind else {
        panic!("mesh")
    };
    assert_eq!(curved.indices.len(), 2 * 8 * 8);
    // The centre of the hyperbolic patch z = u v is at height 1/4.
    let centre = curved.positions[4 * 9 + 4];
    assert!(
        (centre - Vec3::new(0.5, 0.5, 0.25)).length() < 1e-6,
        "{centre}"
    );
}

#[test]
fn interface_shapes_are_invisible_and_interface_quads_are_portals() {
    let l = load(
        r#"WorldBegin
Shape "sphere" "float radius" 1
AttributeBegin
  Translate 0 0 2
  Material "interface"
  Shape "trianglemesh" "point3 P" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] "integer indices" [ 0 1 2  0 2 3 ]
  Shape "trianglemesh" "point3 P" [ 0 0 0  1 0 0  0 1 0 ] "integer indices" [ 0 1 2 ]
  Shape "trianglemesh" "point3 P" [ 0 0 0  1 0 0  3 1 0  0 1 0 ] "integer indices" [ 0 1 2  0 2 3 ]
  Shape "sphere" "float radius" 0.5
AttributeEnd
"#,
    )
    .expect("scene");
    assert!(l.warnings.is_empty(), "{:?}", l.warnings);
    // Only the first sphere is geometry.
    assert_eq!(l.desc.shapes.len(), 1);
    // The parallelogram is a portal, moved by the transform; the triangle and the
    // non-parallelogram quad are not.
    assert_eq!(l.desc.portals.len(), 1);
    let p = l.desc.portals[0];
    assert!((p[0] - Vec3::new(-1.0, -1.0, 2.0)).length() < 1e-6, "{p:?}");
    assert!((p[2] - Vec3::new(1.0, 1.0, 2.0)).length() < 1e-6, "{p:?}");
}

#[test]
fn coordinates_beyond_f32_ray_tracing_are_refused_where_they_are_written() {
    // Valid pbrt-v4 that f32 ray tracing cannot resolve: each is refused at its directive
    // (it used to panic in obvhs' tree builder, abort in Embree or vanish silently).
    let world = "LookAt 0 -3 1  0 0 0  0 0 1\nCamera \"perspective\"\nWorldBegin\n";
    for (body, line) in [
        ("Shape \"sphere\" \"float radius\" 1e30\n", 4),
        (
            "AttributeBegin\nScale 1e30 1e30 1e30\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\nAttributeEnd\n",
            6,
        ),
        (
            "ObjectBegin \"o\"\nShape \"sphere\"\nObjectEnd\nScale 1e20 1e20 1e20\nObjectInstance \"o\"\n",
            8,
        ),
        ("LightSource \"point\" \"point3 from\" [0 0 1e30]\n", 4),
    ] {
        let e = load(&format!("{world}{body}")).err().unwrap_or_default();
        assert!(
            e.starts_with(&format!("test.pbrt:{line}:")) && e.contains("beyond the 1e12 m"),
            "{body}: {e}"
        );
    }
    let e = load("LookAt 0 -3e38 1  0 0 0  0 0 1\nCamera \"perspective\"\nWorldBegin\n")
        .err()
        .unwrap_or_default();
    assert!(
        e.starts_with("test.pbrt:2:") && e.contains("camera position"),
        "{e}"
    );
    // Just inside the limit is fine, with both backends.
    let near = load(&format!("{world}Shape \"sphere\" \"float radius\" 5e11\n")).expect("load");
    for backend in Backend::available() {
        assert!(Scene::build(near.desc.clone(), backend).is_ok());
    }
}

#[test]
fn messages_say_what_was_wanted_and_empty_meshes_are_empty() {
    let e = load("LookAt 0 -3 1  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" [ nan ]\n")
        .err()
        .unwrap_or_default();
    assert!(
        e.contains("test.pbrt:2:36: expected a number in parameter \"float fov\""),
        "{e}"
    );
    // A PLY mesh without faces is an empty shape (it used to stop Embree with "error NONE").
    let dir = scratch("empty-ply");
    std::fs::write(
        dir.join("empty.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
    )
    .expect("ply");
    std::fs::write(
        dir.join("s.pbrt"),
        "LookAt 0 -3 1  0 0 0  0 0 1\nCamera \"perspective\"\nWorldBegin\nShape \"plymesh\" \"string filename\" \"empty.ply\"\nShape \"sphere\"\n",
    )
    .expect("pbrt");
    let l = pbrt::load(&dir.join("s.pbrt"), false).expect("load");
    assert_eq!(l.files.len(), 2, "the scene and its PLY: {:?}", l.files);
    for backend in Backend::available() {
        let scene = Scene::build(l.desc.clone(), backend).expect("an empty mesh is fine");
        assert_eq!(
            shape_at(&scene, 0.5, 0.5),
            Some(1),
            "the sphere is hit ({backend:?})"
        );
    }
}

#[test]
fn motion_blur_renders_the_scene_as_the_shutter_opens() {
    // killeroo-moving.pbrt: StartTime transforms place the object, EndTime ones do not.
    let s = load(
        r#"WorldBegin
        AttributeBegin
          ActiveTransform StartTime
          Translate 1 0 0
          ActiveTransform EndTime
          Translate 0 5 0
          ActiveTransform All
          Translate 0 0 2
          Shape "sphere"
        AttributeEnd
        Shape "sphere""#,
    )
    .expect("load");
    let centers: Vec<Vec3> = s
        .desc
        .shapes
        .iter()
        .map(|sh| match sh.kind {
            ShapeKind::Sphere { center, .. } => center,
            ref other => panic!("sphere expected, found {other:?}"),
        })
        .collect();
    assert_eq!(centers, [Vec3::new(1.0, 0.0, 2.0), Vec3::ZERO]);
    let w: Vec<String> = s.warnings.iter().map(ToString::to_string).collect();
    assert!(
        w.len() == 1 && w[0].contains("motion blur") && w[0].contains("(3 times)"),
        "{w:?}"
    );
}
