//! Real scenes against their reference renders, and the one-feature scenes against pbrt-v4's own images.

use super::*;

/// Where [`judged`] writes fenestra's render of `scene` with `seed`.
fn judged_image(scene: &Path, seed: u32) -> PathBuf {
    let name = scene.file_stem().and_then(|s| s.to_str()).expect("utf-8");
    let parent = scene
        .parent()
        .and_then(|p| p.file_name())
        .and_then(|s| s.to_str());
    tmp(&format!("{}-{name}-{seed}.exr", parent.unwrap_or("")))
}

/// An image's mean red, green and blue.
fn channel_means(path: &Path) -> [f64; 3] {
    let image = Image::read(path).expect("an image");
    let mut sum = [0.0f64; 3];
    for p in &image.pixels {
        for (s, c) in sum.iter_mut().zip([p.r, p.g, p.b]) {
            *s += f64::from(c);
        }
    }
    sum.map(|s| s / image.pixels.len() as f64)
}

/// fenestra's render of a pbrt-v4 scene against a reference image: (mean, reference mean,
/// relative mean error, 8x8 region error), from `fenestra compare`. No warning may be
/// printed but those `allowed` contains.
fn judged(
    scene: &Path,
    reference: &Path,
    (resolution, spp, seed): (&str, u32, u32),
    allowed: &[&str],
) -> (f64, f64, f64, f64) {
    let name = scene.file_stem().and_then(|s| s.to_str()).expect("utf-8");
    let out = judged_image(scene, seed);
    let o = fenestra(&[
        "render",
        scene.to_str().expect("utf-8"),
        "--resolution",
        resolution,
        "--spp",
        &spp.to_string(),
        "--seed",
        &seed.to_string(),
        "--variance",
        "-q",
        "-o",
        out.to_str().expect("utf-8"),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{name}: {err}");
    let warnings: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("warning") && !allowed.iter().any(|a| l.contains(a)))
        .collect();
    assert!(warnings.is_empty(), "{name}: {warnings:?}");
    let o = fenestra(&[
        "compare",
        "--json",
        "--ref",
        reference.to_str().expect("utf-8"),
        out.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    let m = &v[0];
    let (Some(mean), Some(reference)) = (m["mean"].as_f64(), m["ref_mean"].as_f64()) else {
        panic!("{name}: no means in {m}")
    };
    let region_error = m["region_error"].as_f64().unwrap_or(f64::NAN);
    (
        mean,
        reference,
        (mean / reference - 1.0).abs(),
        region_error,
    )
}

/// Two of Bitterli's interiors (CC0, tests/scenes/README.md) rendered small: they load with
/// nothing replaced but the integrator, and their image mean and 8x8 region means agree with
/// two references, each box-filtered or rendered at 64x64, within the stated tolerances:
/// Tungsten's renders (of the scenes as Bitterli wrote them) and pbrt-v4's (of these very
/// files, `scripts/pbrt-judge`'s settings: its path tracer, the scene's path length). The
/// region tolerance covers 256-spp noise; a material or light off by a few percent fails.
/// veach-bidir is lit through a glass egg and a metal lamp: one 256-spp image's mean has a
/// long tail (over 40 seeds, from -0.9% to +5.8% of the reference; a fifth beyond +2%, from
/// rare bright paths), so that scene is judged by the medians over nine seeds, which a
/// systematic error moves as much as the means.
#[test]
fn real_scenes_match_their_reference_renders() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes");
    // (scene, seeds, [(reference, mean tolerance, region tolerance)]); at 256 spp they
    // measured, against Tungsten and pbrt-v4: cornell-box 0.14% and 0.37%, and +0.8% (pbrt-v4
    // renders spectrally: its coloured walls' interreflections differ from RGB's) and 1.1%;
    // veach-bidir (lit indirectly, noisier) medians of 0.4% and 4%, and 0.4% and 3.6%.
    let tungsten = "reference-64.exr";
    let pbrt_v4 = "reference-pbrt-v4-64.exr";
    for (name, seeds, references) in [
        (
            "cornell-box",
            1,
            [(tungsten, 0.01, 0.015), (pbrt_v4, 0.015, 0.02)],
        ),
        (
            "veach-bidir",
            9,
            [(tungsten, 0.03, 0.06), (pbrt_v4, 0.03, 0.06)],
        ),
    ] {
        let dir = scenes.join(name);
        for (reference, mean_tol, region_tol) in references {
            let mut errors: Vec<(f64, f64, f64, f64)> = (0..seeds)
                .map(|seed| {
                    judged(
                        &dir.join("scene-v4.pbrt"),
                        &dir.join(reference),
                        ("64x64", 256, seed),
                        &["Integrator \"bdpt\""],
                    )
                })
                .collect();
            errors.sort_by(|a, b| a.0.total_cmp(&b.0));
            let (mean, reference_mean, mean_error, _) = errors[errors.len() / 2];
            let mut regions: Vec<f64> = errors.iter().map(|e| e.3).collect();
            regions.sort_by(f64::total_cmp);
            let region_error = regions[regions.len() / 2];
            assert!(
                mean_error < mean_tol && region_error < region_tol,
                "{name} against {reference}: median mean {mean:.4} vs {reference_mean:.4} \
                 ({:.2}%, tolerance {}%), median region error {:.2}% (tolerance {}%)",
                100.0 * mean_error,
                100.0 * mean_tol,
                100.0 * region_error,
                100.0 * region_tol
            );
        }
    }
}

/// The one-feature scenes (tests/scenes/features, written by scripts/feature-scenes: one
/// material, relief, texture, light or film setting each on a sphere and a floor) against
/// pbrt-v4's renders of them (64x48, 16384 spp in 8 seeded renders, whose spread gives the
/// reference's variance), at 1024 spp: each must be within noise of pbrt-v4, by z-tests of
/// the image's channel means and of 8x8-pixel regions (significance 1e-4 each, Sidak-corrected;
/// differences under 0.05% of a value aside), unless its difference is a documented choice
/// (`CHOSEN`), which is held to issue 47's bar instead: image mean within
/// 1%, 8x8 region error within 3%, each channel's mean within 2.5% (a colour transform can
/// keep the luminance and move the colours); a named camera sensor to its measured size.
#[test]
fn feature_scenes_render_as_pbrt_v4_renders_them() {
    // Differences that are choices, measured in docs/scenes.md ("One feature at a time"), each
    // held to a bar: image mean, 8x8 region error, worst channel mean.
    const BAR: [f64; 3] = [0.01, 0.03, 0.025];
    const CHOSEN: [(&str, &str, [f64; 3]); 7] = [
        ("texture-sphere", "colours: spectra against RGB", BAR),
        ("coated-diffuse-smooth", "colours: spectra against RGB", BAR),
        ("film-whitebalance", "colours: spectra against RGB", BAR),
        ("coated-diffuse-rough", "pbrt-v4's coat", BAR),
        ("coated-scattering", "pbrt-v4's coat", BAR),
        ("coated-conductor", "pbrt-v4's coat, colours", BAR),
        // Measured +4.1%, 5.6% and 7.4%.
        (
            "film-sensor",
            "a camera's colour response",
            [0.05, 0.065, 0.085],
        ),
    ];
    const FLOOR: f32 = 5e-4;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/features");
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("features")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "pbrt"))
        .collect();
    scenes.sort();
    assert!(scenes.len() >= 15, "{scenes:?}");
    let mut failures = Vec::new();
    for scene in &scenes {
        let name = scene.file_stem().and_then(|s| s.to_str()).expect("utf-8");
        let reference = scene.with_extension("pbrt-v4.exr");
        let (mean, reference_mean, mean_error, region_error) =
            judged(scene, &reference, ("64x48", 1024, 0), &["sensor"]);
        let ours = judged_image(scene, 0);
        let read = |p: &Path| Image::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        let (image, variance) = (read(&ours), read(&ours.with_extension("var.exr")));
        let (theirs, their_variance) = (
            read(&reference),
            read(&scene.with_extension("pbrt-v4.var.exr")),
        );
        let (a, b) = (channel_means(&ours), channel_means(&reference));
        let channel_error = (0..3)
            .map(|c| (a[c] / b[c] - 1.0).abs())
            .fold(0.0, f64::max);
        // Differences under 0.05% of a value are not tested: pbrt-v4's round trip of an RGB
        // colour through its spectra moves a plain sky seen directly by 0.03%, where both
        // images are all but noiseless. The floor is a standard error added to the
        // reference's: to a region's mean through each pixel's variance (64 pixels a region).
        let floored = {
            let mut v = their_variance.clone();
            for (v, r) in v.pixels.iter_mut().zip(&theirs.pixels) {
                *v = *v + *r * *r * (FLOOR * FLOOR * 64.0);
            }
            v
        };
        let whole = whole_image_z(&image, &variance, &theirs, &their_variance, FLOOR.into());
        let regions = fenestra_eval::z_test(&image, &variance, &theirs, Some(&floored), 1e-4, 8)
            .expect("sizes");
        let chosen = CHOSEN.iter().find(|c| c.0 == name);
        let line = format!(
            "{name}: mean {mean:.4} vs pbrt-v4 {reference_mean:.4} ({:+.2}%), region error \
             {:.2}%, worst channel mean {:.2}% off; channel means' z {:.2} {:.2} {:.2}, \
             smallest region p {:.1e} ({} of {} regions fail){}",
            100.0 * (mean / reference_mean - 1.0),
            100.0 * region_error,
            100.0 * channel_error,
            whole[0],
            whole[1],
            whole[2],
            regions.min_p,
            regions.failing,
            regions.tests,
            chosen.map_or(String::new(), |c| format!(" [a choice: {}]", c.1)),
        );
        println!("{line}");
        let failed = match chosen {
            Some(&(_, _, [mean_bar, region_bar, channel_bar])) => {
                mean_error > mean_bar || region_error > region_bar || channel_error > channel_bar
            }
            // Sidak over three channels at 1e-4: |z| beyond 4.06.
            None => whole.iter().any(|z| z.abs() > 4.06) || !regions.passed,
        };
        if failed {
            failures.push(line);
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Each channel's image-mean difference over its standard error, from both images'
/// per-pixel variances of their means and a floor, a fraction of the reference's mean.
fn whole_image_z(
    image: &Image,
    variance: &Image,
    reference: &Image,
    ref_variance: &Image,
    floor: f64,
) -> [f64; 3] {
    let sums = |im: &Image| {
        im.pixels.iter().fold([0.0f64; 3], |mut s, p| {
            for (s, v) in s.iter_mut().zip(p.to_array()) {
                *s += f64::from(v);
            }
            s
        })
    };
    let (x, v, r, rv) = (
        sums(image),
        sums(variance),
        sums(reference),
        sums(ref_variance),
    );
    let n = image.pixels.len() as f64;
    std::array::from_fn(|c| {
        let (mean, ref_mean) = (x[c] / n, r[c] / n);
        (mean - ref_mean) / ((v[c] + rv[c]) / (n * n) + (floor * ref_mean).powi(2)).sqrt()
    })
}
