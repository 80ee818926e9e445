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
