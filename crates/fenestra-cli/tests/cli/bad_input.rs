//! Bad input of every kind: a clear error, a non-zero exit, no panic.

use super::*;

#[test]
fn bad_input_gets_a_clear_error() {
    let out = tmp("err.exr");
    let o = out.to_str().expect("utf-8");
    assert_clear_error(
        &["render", "/no/such/scene.pbrt", "-o", o],
        "/no/such/scene.pbrt:1:1: cannot read scene file",
    );
    assert_clear_error(
        &["render", "builtin:nope", "-o", o],
        "unknown built-in scene 'nope' (available: box-hole",
    );
    assert_clear_error(
        &[
            "render",
            "builtin:glossy-room",
            "--integrator",
            "lp_lt",
            "--light-paths-pilot",
            "99999999",
            "-o",
            o,
        ],
        "light_paths.pilot must lie in [0, 4194304], got 99999999",
    );
    assert_clear_error(
        &[
            "render",
            "builtin:box-hole",
            "--resolution",
            "640x",
            "-o",
            o,
        ],
        "bad resolution '640x'",
    );
    assert_clear_error(
        &[
            "render",
            "builtin:box-hole",
            "--resolution",
            "0x10",
            "-o",
            o,
        ],
        "bad resolution '0x10'",
    );
    assert_clear_error(
        &[
            "render",
            "builtin:box-hole",
            "--integrator",
            "bdpt",
            "-o",
            o,
        ],
        "invalid value 'bdpt' for '--integrator <integrator>'",
    );
    for (args, error) in [
        (
            &["--sky", "--sun", "95,0"][..],
            "--sky: the sun's elevation must lie in [0, 90] degrees",
        ),
        (
            &["--sky", "--sun", "high"][..],
            "--sun: expected ELEVATION,AZIMUTH in degrees",
        ),
        (
            &["--sky", "--sky-turbidity", "12"][..],
            "--sky: turbidity must lie in [1, 10]",
        ),
        (
            &["--sky", "--sun-strength", "-1"][..],
            "--sun-strength must be 0 or more, got -1",
        ),
        (
            &[
                "--sky",
                "--sun-time",
                "2026-06-21T15:00",
                "--location",
                "48.85,2.35",
            ][..],
            "--sun-time: expected a date and time with its UTC offset",
        ),
        (
            &[
                "--sky",
                "--sun-time",
                "2026-06-21T23:00+02:00",
                "--location",
                "48.85,2.35",
            ][..],
            "the sun is 8.1 degrees below the horizon",
        ),
        (
            &[
                "--sky",
                "--sun-time",
                "2026-06-21T15:00Z",
                "--location",
                "91,0",
            ][..],
            "--location must be a latitude in -90..90 and a longitude in -180..180 degrees, got 91,0",
        ),
        (
            &["--environment-rotation", "30"][..],
            "place --environment or --sky; neither is given",
        ),
    ] {
        let mut all = vec!["render", "builtin:box-hole"];
        all.extend(args);
        all.extend(["-o", o]);
        assert_clear_error(&all, error);
    }
    assert_clear_error(
        &[
            "render",
            "builtin:kitchen-72",
            "--integrator",
            "ias",
            "--ias-threshold",
            "0",
            "-o",
            o,
        ],
        "--ias-threshold: ias.threshold must be positive, got 0",
    );
    assert_clear_error(
        &[
            "render",
            "builtin:kitchen-72",
            "--integrator",
            "ias",
            "--ias-sky-regions",
            "100000",
            "-o",
            o,
        ],
        "--ias-sky-regions: ias.sky_regions is at most 4096, got 100000",
    );
    assert_clear_error(
        &[
            "render",
            "builtin:kitchen-72",
            "--integrator",
            "ias",
            "--ias-emitted-rays",
            "5000",
            "-o",
            o,
        ],
        "--ias-emitted-rays: ias.emitted_rays is at most 4096 (eye rays a pixel), got 5000",
    );
    assert_clear_error(
        &[
            "render",
            "builtin:kitchen-72",
            "--integrator",
            "ias",
            "--ias-edge-rays",
            "200",
            "-o",
            o,
        ],
        "--ias-edge-rays: ias.edge_rays is at most 163 (4096 eye rays a pixel), got 200",
    );
    assert_clear_error(
        &[
            "render",
            "builtin:kitchen-72",
            "--integrator",
            "ias",
            "--ias-region-hits",
            "0",
            "-o",
            o,
        ],
        "--ias-region-hits: ias.region_hits must be at least 1",
    );
    assert_clear_error(
        &[
            "render",
            "builtin:box-hole",
            "--integrator",
            "lp_hf",
            "--portal-light-mix",
            "0.5",
            "--light-selection",
            "all",
            "-o",
            o,
        ],
        "--portal-light-mix: portal.light_mix draws one light at a time",
    );
    assert_clear_error(
        &[
            "render",
            "builtin:teapot-box",
            "--integrator",
            "shrc",
            "--sdrc-glossy",
            "path",
            "-o",
            o,
        ],
        "--sdrc-glossy: sdrc.glossy path leaves glossy surfaces to path tracing",
    );
    // An option of another integrator is refused, not ignored.
    assert_clear_error(
        &["render", "builtin:box-hole", "--sdrc-a", "0.3", "-o", o],
        "--sdrc-a: sdrc.a is not read by af_hf with light.selection auto (it reads path, light)",
    );
    assert_clear_error(
        &[
            "render",
            "builtin:box-hole",
            "--light-selection",
            "bvh",
            "--learned-mix",
            "0.3",
            "-o",
            o,
        ],
        "learned.mix is not read by af_hf with light.selection bvh (it reads path, light, bvh)",
    );
    assert_clear_error(
        &["render", "builtin:box-hole", "--spp", "0", "-o", o],
        "--spp must be at least 1",
    );
    assert_clear_error(
        &["render", "builtin:box-hole", "--spp", "-3", "-o", o],
        "error",
    );
    assert_clear_error(
        &["render", "builtin:box-hole", "--time", "-1", "-o", o],
        "--time must be a positive number",
    );
    assert_clear_error(
        &["render", "builtin:box-hole", "-o", "out.png"],
        "must end in .exr",
    );
    assert_clear_error(
        &["render", "builtin:box-hole", "--threads", "0", "-o", o],
        "--threads must be at least 1",
    );
    assert_clear_error(
        &["render", "builtin:box-hole", "--bvh", "optix", "-o", o],
        "unknown ray-query backend 'optix'",
    );
    assert_clear_error(
        &["render", "builtin:box-hole", "--exposure", "nan", "-o", o],
        "--exposure must be a finite number",
    );
    let npy = tmp("bad.npy");
    let n = npy.to_str().expect("utf-8");
    assert_clear_error(
        &["btf", "--noise", "nan", "-o", n],
        "--noise must be a finite",
    );
    assert_clear_error(
        &["btf", "--materials", "1000000000", "-o", n],
        "--materials",
    );
    assert_clear_error(
        &["prt", "--exponent", "nan", "-o", n],
        "exponent (of the Phong lobe) must be a finite",
    );
    assert_clear_error(
        &["raybench", "builtin:box-hole", "--rays", "10000000000000"],
        "at most 100000000",
    );
    assert!(
        !out.exists() && !npy.exists(),
        "no output is written when the input is bad"
    );
    // A scene without light renders, and says it will be black.
    let dark = tmp("dark.pbrt");
    std::fs::write(
        &dark,
        "LookAt 0 -3 1  0 0 0  0 0 1\nCamera \"perspective\"\nWorldBegin\nShape \"sphere\"\n",
    )
    .expect("scene");
    let dark_out = tmp("dark.exr");
    let o = fenestra(&[
        "render",
        dark.to_str().expect("utf-8"),
        "--spp",
        "1",
        "--resolution",
        "4x4",
        "-q",
        "-o",
        dark_out.to_str().expect("utf-8"),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && err.contains("has no light"), "{err}");
    // An image with a NaN pixel has no error to report.
    let mut img = Image::new(4, 4);
    img.pixels[5] = fenestra_core::Rgb::new(f32::NAN, 0.0, 0.0);
    let (nan, good) = (tmp("nan.exr"), tmp("good.exr"));
    img.write_exr(&nan, &Default::default()).expect("write");
    Image::new(4, 4)
        .write_exr(&good, &Default::default())
        .expect("write");
    assert_compare_refused(&good, &nan, "the image has 1 pixels that are not finite");
}

/// Runs `fenestra args` with at most 3 GB of address space (`ulimit -v`), as a machine with
/// little memory would.
fn fenestra_within_3_gb(args: &[&str]) -> std::process::Output {
    Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 3000000 && exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_fenestra"))
        .args(args)
        .output()
        .expect("sh")
}

/// A 377-byte OpenEXR header declaring a 30000x15000 RGB float image (5.4 GB decoded), with
/// `compression` (0 none, 3 zip, 4 piz) and no pixels.
fn exr_declaring_30000x15000(compression: u8) -> Vec<u8> {
    let attr = |out: &mut Vec<u8>, name: &str, kind: &str, value: &[u8]| {
        for text in [name, kind] {
            out.extend(text.as_bytes());
            out.push(0);
        }
        out.extend((value.len() as i32).to_le_bytes());
        out.extend(value);
    };
    let window: Vec<u8> = [0i32, 0, 29999, 14999]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let mut channels = Vec::new();
    for c in ["B", "G", "R"] {
        channels.extend(c.as_bytes());
        channels.extend([0, 2, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0]);
    }
    channels.push(0);
    let mut out = vec![0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0];
    attr(&mut out, "channels", "chlist", &channels);
    attr(&mut out, "compression", "compression", &[compression]);
    attr(&mut out, "dataWindow", "box2i", &window);
    attr(&mut out, "displayWindow", "box2i", &window);
    attr(&mut out, "lineOrder", "lineOrder", &[0]);
    attr(&mut out, "pixelAspectRatio", "float", &1f32.to_le_bytes());
    attr(&mut out, "screenWindowCenter", "v2f", &[0; 8]);
    attr(&mut out, "screenWindowWidth", "float", &1f32.to_le_bytes());
    out.push(0);
    out.extend([0; 64]);
    out
}

/// A 261 KB PNG of 16384 x 16384 black grey pixels (6.4 GB as linear RGB and its conversion).
fn png_of_16384_squared_grey() -> Vec<u8> {
    use std::io::Write;
    let chunk = |out: &mut Vec<u8>, kind: &[u8], data: &[u8]| {
        out.extend((data.len() as u32).to_be_bytes());
        let mut crc = flate2::Crc::new();
        crc.update(kind);
        crc.update(data);
        out.extend(kind);
        out.extend(data);
        out.extend(crc.sum().to_be_bytes());
    };
    let side = 16384u32;
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
    let row = vec![0u8; side as usize + 1];
    for _ in 0..side {
        z.write_all(&row).expect("deflate");
    }
    let mut header = Vec::new();
    header.extend(side.to_be_bytes());
    header.extend(side.to_be_bytes());
    header.extend([8, 0, 0, 0, 0]);
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    chunk(&mut out, b"IHDR", &header);
    chunk(&mut out, b"IDAT", &z.finish().expect("deflate"));
    chunk(&mut out, b"IEND", &[]);
    out
}

/// Sizes a file declares are checked against the file and against the memory the process can
/// get before they are allocated (issue 68, items 1 to 3): a film, EXR headers whose images their
/// files cannot hold, a decompression bomb as an environment and as a glTF texture, each a
/// clear error under a 3 GB address-space limit where each aborted before.
#[test]
fn declared_sizes_are_checked_before_anything_is_allocated() {
    let out = tmp("declared.exr");
    let o = out.to_str().expect("utf-8");
    let refused = |args: &[&str], expect: &[&str]| {
        let run = fenestra_within_3_gb(args);
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{args:?}: {err}");
        assert!(expect.iter().all(|e| err.contains(e)), "{args:?}: {err}");
    };
    for (compression, chunks) in [(0, 15000), (3, 938), (4, 469)] {
        let bomb = tmp(&format!("declares-30000x15000-{compression}.exr"));
        std::fs::write(&bomb, exr_declaring_30000x15000(compression)).expect("write");
        let b = bomb.to_str().expect("utf-8");
        let expect = format!(
            "declares a 30000x15000 image in {chunks} chunks, whose offset table alone ({} bytes) is larger than the file (377 bytes)",
            8 * chunks
        );
        refused(
            &["render", "builtin:box-hole", "--environment", b, "-o", o],
            &[&expect],
        );
        refused(&["compare", "--ref", b, b], &[&expect]);
    }
    let png = tmp("grey-16384.png");
    std::fs::write(&png, png_of_16384_squared_grey()).expect("write");
    let p = png.to_str().expect("utf-8");
    refused(
        &["render", "builtin:box-hole", "--environment", p, "-o", o],
        &["decoding its 16384x16384 pixels needs 6.4 GB of memory and"],
    );
    // The same image as a glTF triangle's base colour.
    let gltf = tmp("bomb-texture.gltf");
    let positions: Vec<u8> = [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    std::fs::write(tmp("bomb-texture.bin"), &positions).expect("write");
    std::fs::write(
        &gltf,
        r#"{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0}], "images": [{"uri": "grey-16384.png"}],
        "buffers": [{"uri": "bomb-texture.bin", "byteLength": 36}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}]}"#,
    )
    .expect("write");
    let g = gltf.to_str().expect("utf-8");
    refused(
        &["render", g, "-o", o],
        &[
            "/images/0: ",
            "decoding its 16384x16384 pixels needs 7.5 GB of memory and",
        ],
    );
    // A film inside the pixel cap that the address-space limit cannot hold (item 1).
    refused(
        &[
            "render",
            "builtin:cornell-box",
            "--resolution",
            "11585x11585",
            "-o",
            o,
        ],
        &[
            "a 11585x11585 film needs",
            "(the process's address-space limit, ulimit -v)",
        ],
    );
    assert!(!out.exists(), "a refused render wrote");
}

/// Light too bright for the film (issue 68 item 17): an environment whose strength overflows
/// its map to infinity is refused by the flag's figures, and a finite but huge one, whose
/// every sample the film drops, is an error with nothing written instead of a black image.
#[test]
fn light_beyond_what_the_film_can_add_up_is_refused() {
    let mut sky = Image::new(8, 4);
    sky.pixels.fill(fenestra_core::Rgb::splat(2.0));
    let map = tmp("bright-sky.exr");
    sky.write_exr(&map, &Default::default()).expect("write");
    let m = map.to_str().expect("utf-8");
    let out = tmp("too-bright.exr");
    let o = out.to_str().expect("utf-8");
    // A triangle under the sky: most camera rays see the environment itself.
    let triangle = tmp("triangle.gltf");
    std::fs::write(
        &triangle,
        r#"{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "buffers": [{"byteLength": 36,
            "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
            "min": [0, 0, 0], "max": [1, 1, 0]}]}"#,
    )
    .expect("write");
    let render = |strength: &str| {
        fenestra(&[
            "render",
            triangle.to_str().expect("utf-8"),
            "--environment",
            m,
            "--environment-strength",
            strength,
            "--resolution",
            "16x12",
            "--spp",
            "2",
            "-q",
            "-o",
            o,
        ])
    };
    let refused = |strength: &str, expect: &str| {
        let run = render(strength);
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{strength}: {err}");
        assert!(err.contains(expect), "{strength}: {err}");
        assert!(!out.exists(), "{strength}: a refused render wrote");
    };
    refused(
        "3e38",
        "strength 300000000000000000000000000000000000000 times the map's brightest texel (2) overflows",
    );
    refused(
        "1e30",
        "were dropped as non-finite or beyond 2^31 in a channel",
    );
    let run = render("1e6");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
}
