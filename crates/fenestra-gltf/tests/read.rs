//! glTF input: a room written as glTF (nested TRS nodes, a mesh used twice, a texture, an
//! emissive quad, a point light in candela) renders as the same room written as pbrt-v4 (the
//! z-test over the image and 8x8 regions); photometric units; cameras by name and index; a
//! GLB reads as its .gltf; bad files give errors naming the file and JSON path.

use fenestra_core::image::Image;
use fenestra_core::Rgb;
use fenestra_gltf::{load, LUMENS_PER_WATT};
use fenestra_render::integrator::{af_hf, PathOptions};
use fenestra_render::light::LightSelection;
use fenestra_render::{render_image, Film, RenderScene, RenderSettings};
use fenestra_scene::{Backend, LightDesc, Scene, SceneDesc};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fenestra-gltf-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// Little-endian bytes of f32s and u16s.
fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}
fn u16s(v: &[u16]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// The room's binary buffer and its views: (offset, length) of floor positions, floor uvs,
/// lamp positions and the shared quad indices.
fn room_buffer() -> (Vec<u8>, [(usize, usize); 4]) {
    let floor = [
        -1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 1.0, 0.0, -1.0, -1.0, 0.0, -1.0,
    ];
    // glTF's v runs down the image: (0, 0) is the texture's top left.
    let uv = [0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    let lamp = [
        -0.1, 0.0, -0.1, 0.1, 0.0, -0.1, 0.1, 0.0, 0.1, -0.1, 0.0, 0.1,
    ];
    let idx = [0u16, 1, 2, 0, 2, 3];
    let mut buf = Vec::new();
    let mut views = [(0, 0); 4];
    for (k, bytes) in [f32s(&floor), f32s(&uv), f32s(&lamp), u16s(&idx)]
        .into_iter()
        .enumerate()
    {
        views[k] = (buf.len(), bytes.len());
        buf.extend(bytes);
    }
    (buf, views)
}

/// The room as glTF JSON, its buffer at `uri`, its floor texture at `texture`.
fn room_json(uri: &str, texture: &str) -> Value {
    let (buf, views) = room_buffer();
    let s45 = std::f32::consts::FRAC_1_SQRT_2;
    json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular", "KHR_materials_emissive_strength"],
        "buffers": [{"uri": uri, "byteLength": buf.len()}],
        "bufferViews": views.iter().map(|(o, l)| json!({"buffer": 0, "byteOffset": o, "byteLength": l})).collect::<Vec<_>>(),
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 0, 1]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.1, 0, -0.1], "max": [0.1, 0, 0.1]},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ],
        "images": [{"uri": texture}],
        "textures": [{"source": 0}],
        "materials": [
            {"name": "plaster", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0},
             "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}},
            {"name": "lamp", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
             "emissiveFactor": [1.0, 0.9, 0.8], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5.0},
             "KHR_materials_specular": {"specularFactor": 0.0}}}
        ],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 3, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": 2}, "indices": 3, "material": 1}]}
        ],
        "cameras": [
            {"name": "front", "type": "perspective", "perspective": {"yfov": 1.0, "aspectRatio": 1.0, "znear": 0.01}},
            {"name": "top", "type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}
        ],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1.0, 0.5, 0.25], "intensity": 2.0 * LUMENS_PER_WATT}
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 4, 5, 6, 7]}],
        "nodes": [
            {"name": "floor", "mesh": 0},
            {"name": "room", "translation": [0, 1, 0], "children": [2, 3]},
            // The floor quad turned up into the back wall (+y -> +z) and pushed back.
            {"name": "back", "mesh": 0, "rotation": [s45, 0, 0, s45], "translation": [0, 0, -1]},
            // ... and into the left wall (+y -> +x), by a matrix.
            {"name": "left", "mesh": 0, "matrix": [0, -1, 0, 0,  1, 0, 0, 0,  0, 0, 1, 0,  -1, 0, 0, 1]},
            {"name": "lamp", "mesh": 1, "translation": [0, 1.9, 0]},
            {"name": "bulb", "translation": [0.5, 1.5, 0.5], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "front camera", "camera": 0, "translation": [0, 1, 3.2]},
            {"name": "top camera", "camera": 1, "translation": [0, 3, 0], "rotation": [-s45, 0, 0, s45]}
        ]
    })
}

/// A 4x2 texture: a ramp of colours along x, darker on its bottom row.
fn write_texture(path: &Path) {
    let mut img = image::RgbImage::new(4, 2);
    for (x, y, p) in img.enumerate_pixels_mut() {
        let v = [200u8, 150, 90, 40][x as usize] / (y as u8 + 1);
        *p = image::Rgb([v, 255 - v, 128]);
    }
    img.save(path).expect("texture");
}

/// The room as a glTF file (external buffer and texture) in `d`.
fn write_room(d: &Path) -> PathBuf {
    std::fs::write(d.join("room.bin"), room_buffer().0).expect("bin");
    write_texture(&d.join("plaster.png"));
    let path = d.join("room.gltf");
    std::fs::write(&path, room_json("room.bin", "plaster.png").to_string()).expect("gltf");
    path
}

/// The same room as pbrt-v4, placed by hand: the texture's v flipped, pbrt's "rgb L" and "rgb I"
/// the glTF emission and intensity / 683, and pbrt's left-handed camera mirrored back as
/// right-handed exporters do (`Scale -1 1 1`); a box filter over the pixel, as glTF has no
/// filter (pbrt-v4's default is a Gaussian).
fn room_pbrt(d: &Path) -> PathBuf {
    let quad = |p: [[f32; 3]; 4], uv: bool| {
        let pts: Vec<String> = p
            .iter()
            .map(|v| format!("{} {} {}", v[0], v[1], v[2]))
            .collect();
        let uv = if uv {
            " \"point2 uv\" [ 0 0  1 0  1 1  0 1 ]"
        } else {
            ""
        };
        format!(
            "Shape \"trianglemesh\" \"point3 P\" [ {} ] \"integer indices\" [ 0 1 2 0 2 3 ]{uv}\n",
            pts.join("  ")
        )
    };
    let mut s = String::from(
        "Scale -1 1 1\nLookAt 0 1 3.2  0 1 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 57.29578 ]\nPixelFilter \"box\" \"float xradius\" 0.5 \"float yradius\" 0.5\nFilm \"rgb\" \"integer xresolution\" [ 32 ] \"integer yresolution\" [ 32 ]\nWorldBegin\n",
    );
    s += "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"plaster.png\"\n";
    s += "Material \"diffuse\" \"texture reflectance\" \"t\"\n";
    s += &quad(
        [[-1., 0., 1.], [1., 0., 1.], [1., 0., -1.], [-1., 0., -1.]],
        true,
    );
    s += &quad(
        [[-1., 0., -1.], [1., 0., -1.], [1., 2., -1.], [-1., 2., -1.]],
        true,
    );
    s += &quad(
        [[-1., 2., 1.], [-1., 0., 1.], [-1., 0., -1.], [-1., 2., -1.]],
        true,
    );
    s += "AttributeBegin\nMaterial \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\nAreaLightSource \"diffuse\" \"rgb L\" [ 5 4.5 4 ]\n";
    s += &quad(
        [
            [-0.1, 1.9, -0.1],
            [0.1, 1.9, -0.1],
            [0.1, 1.9, 0.1],
            [-0.1, 1.9, 0.1],
        ],
        false,
    );
    s += "AttributeEnd\nLightSource \"point\" \"point3 from\" [ 0.5 1.5 0.5 ] \"rgb I\" [ 2 1 0.5 ]\n";
    let path = d.join("room.pbrt");
    std::fs::write(&path, s).expect("pbrt");
    path
}

fn render(mut desc: SceneDesc, spp: u32, seed: u64) -> Film {
    desc.defaults.width = 32;
    desc.defaults.height = 32;
    let scene = RenderScene::new(Scene::build(desc, Backend::default()).expect("scene"));
    let options = PathOptions {
        max_depth: 4,
        ..PathOptions::default()
    };
    let mut integrator = af_hf(options, LightSelection::Power);
    let settings = RenderSettings {
        first_sample: 0,
        spp,
        time_limit: None,
        seed,
    };
    render_image(&mut integrator, &scene, 32, 32, &settings)
        .expect("render")
        .0
}

#[test]
fn a_gltf_room_renders_as_the_same_room_written_as_pbrt() {
    let d = dir("room");
    let gltf = load(&write_room(&d), None).expect("glTF");
    assert!(gltf.warnings.is_empty(), "{:?}", gltf.warnings);
    let pbrt = fenestra_pbrt::load(&room_pbrt(&d), true).expect("pbrt");
    let (a, b) = (render(gltf.desc, 256, 1), render(pbrt.desc, 256, 2));
    let t = fenestra_eval::agreement(&a.estimate(), &b.estimate(), 0.01, 8).expect("sizes");
    assert!(t.passed(), "glTF vs pbrt: {t:?}");
    // Not vacuous: the room with its texture's rows swapped (glTF's v not flipped) differs.
    let d2 = dir("room-flipped");
    let flipped = write_room(&d2);
    let img = image::open(d2.join("plaster.png")).expect("png").flipv();
    img.save(d2.join("plaster.png")).expect("png");
    let c = render(load(&flipped, None).expect("glTF").desc, 256, 3);
    let t = fenestra_eval::agreement(&c.estimate(), &b.estimate(), 0.01, 8).expect("sizes");
    assert!(!t.passed(), "a flipped texture went unnoticed");
}

#[test]
fn a_point_light_of_683_candela_is_one_watt_per_steradian() {
    let d = dir("units");
    let loaded = load(&write_room(&d), None).expect("glTF");
    let intensity = loaded.desc.lights.iter().find_map(|l| match l {
        LightDesc::Point { intensity, .. } => Some(*intensity),
        _ => None,
    });
    assert_eq!(intensity, Some(Rgb::new(2.0, 1.0, 0.5)));
}

#[test]
fn cameras_are_picked_by_name_or_index() {
    let d = dir("cameras");
    let path = write_room(&d);
    let front = load(&path, None).expect("default");
    assert_eq!(front.cameras, vec!["front".to_string(), "top".to_string()]);
    assert_eq!(
        front.desc.camera.position,
        load(&path, Some("front"))
            .expect("name")
            .desc
            .camera
            .position
    );
    let top = load(&path, Some("1")).expect("index").desc.camera;
    assert!(
        (top.position.y - 3.0).abs() < 1e-6 && top.forward().y < -0.999,
        "{top:?}"
    );
    // The front camera's aspect ratio, 1.
    assert_eq!(
        (front.desc.defaults.width, front.desc.defaults.height),
        (960, 960)
    );
    // What stands in is said: a framing camera for orthographic ones, 16:9 for an aspect
    // ratio beyond 10:1.
    let edited = |name: &str, edit: &dyn Fn(&mut Value)| {
        let mut json = room_json("room.bin", "plaster.png");
        edit(&mut json);
        let p = d.join(name);
        std::fs::write(&p, json.to_string()).expect("gltf");
        load(&p, None).expect("glTF").warnings
    };
    let warnings = edited("ortho.gltf", &|j| {
        for c in j["cameras"].as_array_mut().expect("cameras") {
            *c = json!({"type": "orthographic",
                        "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": 0.01, "zfar": 100.0}});
        }
    });
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("2 orthographic camera(s)")),
        "{warnings:?}"
    );
    // A required extension listed only as required (not as used, as the spec asks).
    let warnings = edited("required.gltf", &|j| {
        j["extensionsRequired"] = json!(["KHR_draco_mesh_compression"])
    });
    assert!(
        warnings.iter().any(|w| w.contains(
            "/extensionsRequired: extension KHR_draco_mesh_compression is required but not supported"
        )),
        "{warnings:?}"
    );
    let warnings = edited("wide.gltf", &|j| {
        j["cameras"][0]["perspective"]["aspectRatio"] = json!(20.0)
    });
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("aspectRatio 20 lies beyond 10:1")),
        "{warnings:?}"
    );
    let err = load(&path, Some("side"))
        .err()
        .expect("unknown camera")
        .to_string();
    assert!(
        err.contains("no camera \"side\"") && err.contains("0: front, 1: top"),
        "{err}"
    );
}

/// The room as one .glb: JSON chunk, then the buffer and the texture in the BIN chunk.
#[test]
fn a_glb_reads_as_its_gltf() {
    let d = dir("glb");
    let gltf = write_room(&d);
    let (mut bin, _) = room_buffer();
    let mut json = room_json("unused", "unused");
    let png = std::fs::read(d.join("plaster.png")).expect("png");
    let png_at = bin.len();
    bin.extend(&png);
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    json["buffers"] = json!([{"byteLength": bin.len()}]);
    json["bufferViews"]
        .as_array_mut()
        .expect("views")
        .push(json!({"buffer": 0, "byteOffset": png_at, "byteLength": png.len()}));
    json["images"] = json!([{"bufferView": 4, "mimeType": "image/png"}]);
    let mut text = json.to_string().into_bytes();
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let mut glb = Vec::new();
    glb.extend(b"glTF");
    glb.extend(2u32.to_le_bytes());
    glb.extend(((12 + 8 + text.len() + 8 + bin.len()) as u32).to_le_bytes());
    glb.extend((text.len() as u32).to_le_bytes());
    glb.extend(b"JSON");
    glb.extend(&text);
    glb.extend((bin.len() as u32).to_le_bytes());
    glb.extend(b"BIN\0");
    glb.extend(&bin);
    std::fs::write(d.join("room.glb"), &glb).expect("glb");
    let (a, b) = (
        load(&gltf, None).expect("gltf").desc,
        load(&d.join("room.glb"), None).expect("glb").desc,
    );
    assert_eq!(format!("{:?}", a.shapes), format!("{:?}", b.shapes));
    assert_eq!(a.materials.len(), b.materials.len());
    // A header declaring fewer bytes than itself (found by fuzzing: the gltf crate's
    // arithmetic overflowed).
    let mut short = glb.clone();
    short[8..12].copy_from_slice(&4u32.to_le_bytes());
    std::fs::write(d.join("short.glb"), &short).expect("glb");
    let err = load(&d.join("short.glb"), None)
        .err()
        .expect("short")
        .to_string();
    assert!(err.contains("GLB header declares 4 bytes"), "{err}");
    // Truncated: the BIN chunk cut short.
    std::fs::write(d.join("cut.glb"), &glb[..glb.len() - 100]).expect("glb");
    let err = load(&d.join("cut.glb"), None)
        .err()
        .expect("truncated")
        .to_string();
    assert!(err.contains("cut.glb"), "{err}");
}

/// `load` on the room with `edit` applied to its JSON fails with a message containing
/// every one of `expect`.
fn assert_refused(name: &str, edit: impl FnOnce(&mut Value, &Path), expect: &[&str]) {
    let d = dir(name);
    write_room(&d);
    let mut json = room_json("room.bin", "plaster.png");
    edit(&mut json, &d);
    let path = d.join("bad.gltf");
    std::fs::write(&path, json.to_string()).expect("gltf");
    let err = load(&path, None)
        .err()
        .map(|e| e.to_string())
        .unwrap_or_else(|| panic!("{name}: loaded"));
    for e in expect {
        assert!(err.contains(e), "{name}: {err:?} lacks {e:?}");
    }
}

#[test]
fn bad_files_give_errors_with_file_and_json_path() {
    assert_refused(
        "index",
        |j, _| j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(41),
        &["bad.gltf: /meshes/0/primitives/0/attributes/TEXCOORD_0: index out of range"],
    );
    // gltf-json's own checks indexed this one unchecked (found by fuzzing).
    assert_refused(
        "position",
        |j, _| j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(99),
        &["bad.gltf: /meshes/0/primitives/0/attributes/POSITION: accessor 99 out of range (4 accessors)"],
    );
    assert_refused(
        "image",
        |j, _| j["images"][0] = json!({"name": "nowhere"}),
        &["bad.gltf: /images/0: has neither a uri nor a bufferView"],
    );
    assert_refused(
        "camera",
        |j, _| j["cameras"][0]["type"] = json!("orthographic"),
        &["bad.gltf: /cameras/0/orthographic: required value missing"],
    );
    assert_refused(
        "truncated",
        |_, d| {
            let bin = room_buffer().0;
            std::fs::write(d.join("room.bin"), &bin[..bin.len() - 10]).expect("bin");
        },
        &["bad.gltf: /buffers/0:", "truncated"],
    );
    assert_refused(
        "count",
        |j, _| j["accessors"][0]["count"] = json!(400),
        &["/accessors/0:", "do not fit"],
    );
    assert_refused(
        "texture",
        |j, _| j["images"][0]["uri"] = json!("missing.png"),
        &["bad.gltf: /images/0: cannot read", "missing.png"],
    );
    // A device is read without end (until memory runs out), a folder not at all; an absolute
    // path is no glTF's own file.
    #[cfg(unix)]
    assert_refused(
        "device",
        |j, _| j["buffers"][0]["uri"] = json!("/dev/zero"),
        &["bad.gltf: /buffers/0: names the absolute path /dev/zero"],
    );
    #[cfg(unix)]
    assert_refused(
        "device beside",
        |j, d| {
            let _ = std::fs::remove_file(d.join("zero.bin"));
            std::os::unix::fs::symlink("/dev/zero", d.join("zero.bin")).expect("link");
            j["buffers"][0]["uri"] = json!("zero.bin");
        },
        &["bad.gltf: /buffers/0:", "zero.bin is not a regular file"],
    );
    assert_refused(
        "folder",
        |j, d| {
            std::fs::create_dir_all(d.join("textures")).expect("folder");
            j["images"][0]["uri"] = json!("textures");
        },
        &["bad.gltf: /images/0:", "textures is not a regular file"],
    );
    // Elements 8 bytes apart whose size is 12 would each read a third of the next.
    assert_refused(
        "stride",
        |j, _| j["bufferViews"][0]["byteStride"] = json!(8),
        &["bad.gltf: /bufferViews/0: byteStride 8 is smaller than its accessor's 12-byte elements"],
    );
    assert_refused(
        "uv count",
        |j, _| j["accessors"][1]["count"] = json!(3),
        &["bad.gltf: /meshes/0/primitives/0/attributes/TEXCOORD_0: 3 values for 4 vertices"],
    );
    assert_refused(
        "two parents",
        |j, _| j["nodes"][0]["children"] = json!([3]),
        &["bad.gltf: /nodes/3: reached a second time", "second parent"],
    );
    assert_refused(
        "cycle",
        |j, _| j["nodes"][3]["children"] = json!([1]),
        &["/nodes/1:", "cycle"],
    );
    // Indices read from the uv floats: 16256 and the like, beyond the 4 vertices.
    assert_refused(
        "vertex",
        |j, _| j["accessors"][3]["bufferView"] = json!(1),
        &[
            "/meshes/0/primitives/0/indices: vertex index",
            "out of range (4 vertices)",
        ],
    );
    assert_refused(
        "type",
        |j, _| j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(0),
        &["/accessors/0: has type Vec3, expected 2 components"],
    );
    assert_refused("json", |j, _| *j = json!({"asset": 3}), &["bad.gltf:"]);
}

#[test]
fn a_flat_texture_ramp_reads_as_srgb() {
    // The texel 200 in sRGB is linear 0.578: the texture decodes as colour.
    let d = dir("srgb");
    let loaded = load(&write_room(&d), None).expect("glTF");
    let fenestra_scene::Material::MetallicRoughness(m) = &loaded.desc.materials[1] else {
        panic!("{:?}", loaded.desc.materials[1]);
    };
    let t = m.base_color_texture.as_ref().expect("texture");
    let texel: &Image = &t.image;
    assert!((texel.get(0, 0).r - fenestra_core::image::srgb_to_linear(200.0 / 255.0)).abs() < 1e-6);
}

/// A cheap fuzzer: 400 corruptions of the room (bytes of its JSON, buffer or texture
/// overwritten, or the file cut short) each load or fail with an error, never panic.
#[test]
fn corrupted_files_never_panic() {
    let d = dir("fuzz");
    let path = write_room(&d);
    let originals: Vec<(PathBuf, Vec<u8>)> = ["room.gltf", "room.bin", "plaster.png"]
        .iter()
        .map(|f| (d.join(f), std::fs::read(d.join(f)).expect("read")))
        .collect();
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    for case in 0..400 {
        let (file, bytes) = &originals[next(3)];
        let mut bad = bytes.clone();
        match next(3) {
            0 => bad.truncate(next(bad.len())),
            _ => {
                for _ in 0..1 + next(4) {
                    let i = next(bad.len());
                    bad[i] = next(256) as u8;
                }
            }
        }
        std::fs::write(file, &bad).expect("write");
        let result = std::panic::catch_unwind(|| load(&path, None).map(|_| ()));
        assert!(
            result.is_ok(),
            "case {case}: loading a corrupted {} panicked",
            file.display()
        );
        std::fs::write(file, bytes).expect("restore");
    }
}

/// A MASK material reads its cut-out from the base colour texture's alpha channel (as
/// stored, not sRGB-decoded), and its colour from the same image's RGB.
#[test]
fn a_masked_material_reads_its_alpha_channel() {
    let d = dir("mask");
    write_room(&d);
    let mut img = image::RgbaImage::new(2, 1);
    img.put_pixel(0, 0, image::Rgba([200, 100, 50, 255]));
    img.put_pixel(1, 0, image::Rgba([200, 100, 50, 64]));
    img.save(d.join("leaf.png")).expect("png");
    let mut json = room_json("room.bin", "leaf.png");
    json["materials"][0]["alphaMode"] = json!("MASK");
    json["materials"][0]["alphaCutoff"] = json!(0.3);
    std::fs::write(d.join("leaf.gltf"), json.to_string()).expect("gltf");
    let loaded = load(&d.join("leaf.gltf"), None).expect("glTF");
    let fenestra_scene::Material::MetallicRoughness(m) = &loaded.desc.materials[1] else {
        panic!("{:?}", loaded.desc.materials[1]);
    };
    let alpha = m.alpha.as_ref().expect("a cut-out");
    assert_eq!(
        alpha.mode,
        fenestra_scene::material::AlphaMode::Mask { cutoff: 0.3 }
    );
    let a = &alpha.texture.as_ref().expect("alpha texture").image;
    assert_eq!((a.get(0, 0).r, a.get(1, 0).r), (1.0, 64.0 / 255.0));
    let c = &m.base_color_texture.as_ref().expect("colour").image;
    let srgb = fenestra_core::image::srgb_to_linear(200.0 / 255.0);
    assert!((c.get(1, 0).r - srgb).abs() < 1e-6);
}

/// KHR_mesh_quantization's integer attributes (plain shorts for positions, with a padded
/// stride; normalised bytes for uvs) and a sparse accessor (zeros without a buffer view, two
/// vertices substituted) read as the floats they stand for.
#[test]
fn quantized_and_sparse_accessors_read_as_their_floats() {
    let d = dir("quantized");
    let mut buf = Vec::new();
    for p in [[-2i16, 0, 3], [5, 0, 3], [5, 0, -7]] {
        buf.extend(p.iter().flat_map(|v| v.to_le_bytes()));
        buf.extend([0u8, 0]); // stride 8
    }
    let uv_at = buf.len();
    buf.extend([0u8, 255, 0, 0, 255, 0, 0, 0, 255, 255, 0, 0]); // (0,1) (1,0) (1,1), stride 4
    let idx_at = buf.len();
    buf.extend([1u8, 2, 0, 0]);
    let val_at = buf.len();
    buf.extend(f32s(&[1.0, 0.0, 0.0, 0.0, 0.0, 1.0]));
    std::fs::write(d.join("q.bin"), &buf).expect("bin");
    let json = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_mesh_quantization"],
        "extensionsRequired": ["KHR_mesh_quantization"],
        "buffers": [{"uri": "q.bin", "byteLength": buf.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": uv_at, "byteStride": 8},
            {"buffer": 0, "byteOffset": uv_at, "byteLength": 12, "byteStride": 4},
            {"buffer": 0, "byteOffset": idx_at, "byteLength": 2},
            {"buffer": 0, "byteOffset": val_at, "byteLength": 24}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5122, "count": 3, "type": "VEC3", "min": [-2, 0, -7], "max": [5, 0, 3]},
            {"bufferView": 1, "componentType": 5121, "normalized": true, "count": 3, "type": "VEC2"},
            {"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 0, 1],
             "sparse": {"count": 2, "indices": {"bufferView": 2, "componentType": 5121},
                        "values": {"bufferView": 3}}}
        ],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}}]},
            {"primitives": [{"attributes": {"POSITION": 2}}]}
        ],
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"mesh": 1, "translation": [0, 1, 0]}]
    });
    std::fs::write(d.join("q.gltf"), json.to_string()).expect("gltf");
    let loaded = load(&d.join("q.gltf"), None).expect("glTF");
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let mesh = |i: usize| match &loaded.desc.shapes[i].kind {
        fenestra_scene::ShapeKind::Mesh(m) => m.clone(),
        other => panic!("{other:?}"),
    };
    let (a, b) = (mesh(0), mesh(1));
    let v = |x: f32, y: f32, z: f32| fenestra_core::Vec3::new(x, y, z);
    assert_eq!(
        a.positions,
        vec![v(-2.0, 0.0, 3.0), v(5.0, 0.0, 3.0), v(5.0, 0.0, -7.0)]
    );
    // glTF's v flipped: (0, 1) -> (0, 0) and so on.
    let uv = |x: f32, y: f32| fenestra_core::Vec2::new(x, y);
    assert_eq!(a.uvs, Some(vec![uv(0.0, 0.0), uv(1.0, 1.0), uv(1.0, 0.0)]));
    assert_eq!(
        b.positions,
        vec![v(0.0, 1.0, 0.0), v(1.0, 1.0, 0.0), v(0.0, 1.0, 1.0)]
    );
}

/// KHR_texture_transform: a texture offset by (0.25, 0.5) and scaled by (0.5, 0.5) in glTF's
/// uv space (v down the image) looks up, at any point, the texel the untransformed texture
/// has at the transformed coordinates.
#[test]
fn texture_transforms_map_gltf_coordinates() {
    let d = dir("transform");
    write_room(&d);
    let mut json = room_json("room.bin", "plaster.png");
    json["extensionsUsed"]
        .as_array_mut()
        .expect("used")
        .push(json!("KHR_texture_transform"));
    json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
        json!({"KHR_texture_transform": {"offset": [0.25, 0.5], "scale": [0.5, 0.5]}});
    std::fs::write(d.join("t.gltf"), json.to_string()).expect("gltf");
    let loaded = load(&d.join("t.gltf"), None).expect("glTF");
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let fenestra_scene::Material::MetallicRoughness(m) = &loaded.desc.materials[1] else {
        panic!("{:?}", loaded.desc.materials[1]);
    };
    let t = m.base_color_texture.as_ref().expect("texture");
    let plain = fenestra_scene::ImageTexture::new(t.image.clone(), t.path.clone());
    for (ug, vg) in [(0.1f32, 0.2f32), (0.7, 0.9), (0.45, 0.05)] {
        // The mesh holds (u, 1 - v); the transform acts on glTF's (u, v).
        let at = fenestra_core::Vec2::new(ug, 1.0 - vg);
        let (su, sv) = (0.5 * ug + 0.25, 0.5 * vg + 0.5);
        let expect = plain.lookup(fenestra_core::Vec2::new(su, 1.0 - sv));
        let got = t.lookup(at);
        assert!(
            (got - expect).max_component().abs() < 1e-5
                && (expect - got).max_component().abs() < 1e-5,
            "({ug}, {vg}): {got:?} vs {expect:?}"
        );
    }
}
