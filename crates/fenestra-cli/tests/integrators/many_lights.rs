//! ias and the learned light sampler from the command line.

use super::*;

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
