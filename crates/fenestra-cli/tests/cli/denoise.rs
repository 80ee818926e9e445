//! `--denoise` and `--features`: OIDN's image written beside the render (never over it or
//! an input), closer to the reference than the raw one; the features as the EXR's layers;
//! merged parts denoised; a clear error where OIDN is not installed.

use super::*;
use fenestra_core::image::{read_exr_channel_names, read_exr_layer};
use fenestra_eval::metrics;

fn sidecar(exr: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(exr.with_extension("json")).expect("sidecar");
    serde_json::from_str(&text).expect("JSON")
}

fn ok(o: &std::process::Output) {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn a_denoised_4_spp_render_is_closer_to_its_reference_than_the_raw_one() {
    let cornell = |spp: &str, seed: &str, out: &Path, extra: &[&str]| {
        let mut args = vec![
            "render",
            "builtin:cornell-box",
            "--resolution",
            "48x48",
            "--spp",
            spp,
            "--seed",
            seed,
            "-o",
            out.to_str().expect("utf-8"),
            "-q",
        ];
        args.extend_from_slice(extra);
        fenestra(&args)
    };
    let reference = tmp("dn-ref.exr");
    ok(&cornell("1024", "100", &reference, &[]));
    let reference = Image::read(&reference).expect("reference");
    for seed in ["1", "2", "3"] {
        let out = tmp(&format!("dn-{seed}.exr"));
        ok(&cornell("4", seed, &out, &["--denoise"]));
        let denoised = out.with_extension("denoised.exr");
        let rel = |p: &Path| {
            let m = metrics::compare(&Image::read(p).expect("image"), &reference).expect("compare");
            m.rel_mse
        };
        // Measured: 4.6-7.4x lower relative MSE over these seeds.
        let (raw, clean) = (rel(&out), rel(&denoised));
        assert!(
            clean < raw / 3.0,
            "seed {seed}: relative MSE {raw:.4} raw, {clean:.4} denoised"
        );
        assert!(Image::read(&denoised.with_extension("png")).is_ok());
        let s = sidecar(&out);
        let d = &s["denoiser"];
        assert_eq!(d["denoiser"], "Intel Open Image Denoise");
        assert_eq!(d["version"], "2.5.1");
        assert_eq!(
            (&d["mode"], &d["features"]),
            (&"accurate".into(), &true.into())
        );
        let channels = read_exr_channel_names(&out).expect("channels");
        for c in [
            "albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z", "R",
        ] {
            assert!(channels.iter().any(|n| n == c), "{c} not in {channels:?}");
        }
        // The denoised EXR holds the picture alone.
        assert_eq!(
            read_exr_channel_names(&denoised).expect("channels"),
            ["B", "G", "R"]
        );
    }
}

#[test]
fn features_alone_add_layers_and_change_no_pixel() {
    let (plain, featured) = (tmp("ft-plain.exr"), tmp("ft-features.exr"));
    ok(&render(&plain, &[]));
    ok(&render(&featured, &["--features"]));
    assert_eq!(
        Image::read(&plain).expect("plain"),
        Image::read(&featured).expect("featured")
    );
    assert_eq!(read_exr_channel_names(&plain).expect("channels").len(), 3);
    assert_eq!(
        read_exr_channel_names(&featured).expect("channels").len(),
        9
    );
    assert!(!featured.with_extension("denoised.exr").exists());
    assert!(sidecar(&featured).get("denoiser").is_none());
    // As files of their own beside a plain EXR: the same features.
    let files = tmp("ft-files.exr");
    ok(&render(&files, &["--features", "files"]));
    assert_eq!(read_exr_channel_names(&files).expect("channels").len(), 3);
    for (layer, channels, file) in [
        ("albedo", ["R", "G", "B"], "albedo.exr"),
        ("normal", ["X", "Y", "Z"], "normal.exr"),
    ] {
        let beside = Image::read(&files.with_extension(file)).expect("feature file");
        assert_eq!(
            beside,
            read_exr_layer(&featured, layer, channels).expect("layer"),
            "{layer}"
        );
    }
    let o = render(&tmp("ft-bad.exr"), &["--features", "pfm"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("layers") && err.contains("files"),
        "{err}"
    );
}

#[test]
fn merged_parts_with_features_denoise_and_parts_without_them_do_not_merge_with_them() {
    let part = |name: &str, range: &str, extra: &[&str]| {
        let out = tmp(name);
        let mut args = vec!["--samples", range];
        args.extend_from_slice(extra);
        let o = fenestra(
            &[
                &[
                    "render",
                    "builtin:box-hole",
                    "--resolution",
                    "24x16",
                    "-o",
                    out.to_str().expect("utf-8"),
                    "-q",
                ][..],
                &args,
            ]
            .concat(),
        );
        ok(&o);
        out
    };
    let a = part("mf-a.exr", "0..3", &["--features"]);
    let b = part("mf-b.exr", "3..8", &["--features"]);
    let merged = tmp("mf-merged.exr");
    let m = |parts: &[&Path], extra: &[&str]| {
        let mut args: Vec<&str> = vec!["merge", "-o", merged.to_str().expect("utf-8")];
        args.extend(parts.iter().map(|p| p.to_str().expect("utf-8")));
        args.extend_from_slice(extra);
        fenestra(&args)
    };
    ok(&m(&[&a, &b], &["--denoise", "fast"]));
    assert!(merged.with_extension("denoised.exr").exists());
    assert_eq!(sidecar(&merged)["denoiser"]["mode"], "fast");
    // The whole render's features, bit for bit.
    let whole = tmp("mf-whole.exr");
    ok(&fenestra(&[
        "render",
        "builtin:box-hole",
        "--resolution",
        "24x16",
        "--spp",
        "8",
        "--features",
        "-o",
        whole.to_str().expect("utf-8"),
        "-q",
    ]));
    assert_eq!(
        Image::read(&merged).expect("merged"),
        Image::read(&whole).expect("whole")
    );
    for (layer, channels) in [("albedo", ["R", "G", "B"]), ("normal", ["X", "Y", "Z"])] {
        let read = |p: &Path| read_exr_layer(p, layer, channels).expect("layer");
        assert_eq!(read(&merged), read(&whole), "{layer}");
    }
    let c = part("mf-c.exr", "3..8", &[]);
    let o = m(&[&a, &c], &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("denoising features"),
        "{err}"
    );
}

#[test]
fn denoise_without_oidn_is_a_clear_error_before_anything_is_rendered() {
    let out = tmp("no-oidn.exr");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_fenestra"))
        .args([
            "render",
            "builtin:box-hole",
            "--spp",
            "1",
            "--denoise",
            "-o",
        ])
        .arg(&out)
        .env("FENESTRA_OIDN", tmp("no-oidn-here"))
        .env("HOME", tmp("no-home"))
        .env_remove("LD_LIBRARY_PATH")
        .output()
        .expect("run");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{err}");
    assert!(
        err.contains("Intel Open Image Denoise 2 was not found"),
        "{err}"
    );
    assert!(
        err.contains("scripts/setup") && err.contains("FENESTRA_OIDN"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.exists() && !out.with_extension("json").exists());
}

#[test]
fn the_denoised_image_never_replaces_an_input() {
    let out = tmp("dn-input.exr");
    let input = out.with_extension("denoised.exr");
    ok(&render(&input, &[]));
    let before = std::fs::read(&input).expect("input");
    let o = render(
        &out,
        &["--denoise", "--reference", input.to_str().expect("utf-8")],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("denoised image"),
        "{err}"
    );
    assert_eq!(std::fs::read(&input).expect("input"), before);
}

#[test]
fn snapshots_are_denoised_too_and_those_beside_a_complete_render_go_when_it_is_done() {
    let (plain, watched) = (tmp("dns-plain.exr"), tmp("dns-watched.exr"));
    let args = ["--seed", "5", "--denoise", "--json"];
    ok(&render(&plain, &args));
    let o = render(
        &watched,
        &[&args[..], &["--snapshot-every", "1e-9"]].concat(),
    );
    ok(&o);
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    assert_eq!(s["extra"]["snapshots"].as_f64(), Some(3.0), "{s}");
    let denoised = |p: &Path| Image::read(&p.with_extension("denoised.exr")).expect("denoised");
    assert_eq!(denoised(&plain), denoised(&watched));
    // Over a complete render the snapshots (denoised ones too) go beside it, then away.
    ok(&render(
        &watched,
        &["--seed", "6", "--denoise", "--snapshot-every", "1e-9", "-q"],
    ));
    for beside in [
        "interrupted.exr",
        "interrupted.denoised.exr",
        "interrupted.denoised.png",
    ] {
        assert!(!watched.with_extension(beside).exists(), "{beside} left");
    }
    assert_eq!(sidecar(&watched)["seed"], 6);
}

#[test]
fn every_integrator_takes_the_same_features() {
    let features = |scene: &str, integrator: &str, extra: &[&str]| {
        let out = tmp(&format!("fi-{integrator}.exr"));
        let mut args = vec!["render", scene, "--resolution", "24x16", "-q"];
        args.extend(["--integrator", integrator, "--features", "-o"]);
        args.push(out.to_str().expect("utf-8"));
        // ias decides its own samples.
        if integrator != "ias" {
            args.extend(["--spp", "4"]);
        }
        args.extend_from_slice(extra);
        ok(&fenestra(&args));
        let albedo = read_exr_layer(&out, "albedo", ["R", "G", "B"]).expect("albedo");
        let normal = read_exr_layer(&out, "normal", ["X", "Y", "Z"]).expect("normal");
        (albedo.mean(), normal.mean())
    };
    let off = |x: fenestra_core::Rgb, y: fenestra_core::Rgb| {
        (0..3)
            .map(|c| (x.to_array()[c] - y.to_array()[c]).abs())
            .fold(0.0, f32::max)
    };
    // hf, lp_hf and sdrc read them off their paths, ias and lt (light paths alone) take
    // feature samples of their own: the same as af_hf's up to anti-aliasing at the edges
    // (other positions in the pixels).
    let portals: &[&str] = &["--portals", "auto", "--no-portal-cache"];
    for (scene, integrators) in [
        (
            "builtin:box-hole",
            &[
                ("hf", &[][..]),
                ("lp_hf", &[][..]),
                ("sdrc", &[][..]),
                ("ias", &[][..]),
            ][..],
        ),
        ("builtin:glossy-room", &[("lt", portals)][..]),
    ] {
        let (albedo, normal) = features(scene, "af_hf", &[]);
        assert!(albedo.g > 0.1, "{scene}: {albedo:?}");
        for &(integrator, extra) in integrators {
            let (a, n) = features(scene, integrator, extra);
            assert!(
                off(a, albedo) < 0.01,
                "{integrator}: albedo {a:?}, af_hf's {albedo:?}"
            );
            assert!(
                off(n, normal) < 0.01,
                "{integrator}: normal {n:?}, af_hf's {normal:?}"
            );
        }
    }
}
