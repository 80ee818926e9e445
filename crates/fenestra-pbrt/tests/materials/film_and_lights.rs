//! Pixel filters, the film's exposure and white balance, area lights' power, and the values pbrt-v4 refuses or clamps.

use super::*;

#[test]
fn pixel_filters_as_pbrt_v4_defines_them() {
    use fenestra_scene::filter::{FilterShape, PixelFilter};
    let filter = |header: &str| {
        load(&format!("{header}\nWorldBegin\n")).map(|s| (s.desc.camera.filter, s.warnings.len()))
    };
    // No PixelFilter: pbrt-v4's gaussian of radius 1.5 and sigma 0.5.
    assert_eq!(filter(""), Ok((PixelFilter::pbrt_default(), 0)));
    assert_eq!(
        filter("PixelFilter \"triangle\""),
        Ok((PixelFilter::new(FilterShape::Triangle, Vec2::splat(2.0)), 0))
    );
    assert_eq!(
        filter("PixelFilter \"gaussian\" \"float xradius\" 2 \"float sigma\" 0.7"),
        Ok((
            PixelFilter::new(FilterShape::Gaussian { sigma: 0.7 }, Vec2::new(2.0, 1.5)),
            0
        ))
    );
    assert_eq!(
        filter("PixelFilter \"box\""),
        Ok((PixelFilter::default(), 0))
    );
    // Negative lobes cannot be importance-sampled: said.
    let (mitchell, warnings) = filter("PixelFilter \"mitchell\"").expect("mitchell");
    assert!(matches!(mitchell.shape(), FilterShape::Mitchell { .. }) && warnings == 1);
    for (header, says) in [
        (
            "PixelFilter \"lanczos\"",
            "1:1: unknown PixelFilter \"lanczos\"",
        ),
        (
            "PixelFilter \"box\" \"float xradius\" 0",
            "PixelFilter radii must be in (0, 64]",
        ),
        (
            "PixelFilter \"gaussian\" \"float sigma\" -1",
            "sigma and tau positive",
        ),
    ] {
        let e = filter(header).expect_err(says);
        assert!(e.contains(says), "{e}");
    }
}

#[test]
fn impossible_light_and_material_values_are_refused_or_clamped_as_pbrt_does() {
    let world = "LookAt 0 -3 1  0 0 0  0 0 1\nCamera \"perspective\"\nWorldBegin\n";
    let e = load(&format!(
        "{world}LightSource \"infinite\" \"rgb L\" [-1 -1 -1]\n"
    ))
    .err()
    .unwrap_or_default();
    assert!(
        e.starts_with("test.pbrt:4:") && e.contains("negative"),
        "{e}"
    );
    // pbrt-v4 clamps reflectances to [0, 1]: so does the reader, and says so.
    let l = load(&format!(
        "{world}Material \"diffuse\" \"rgb reflectance\" [1e30 0.5 2]\nShape \"sphere\"\n"
    ))
    .expect("load");
    assert!(
        l.warnings.iter().any(|w| w.what.contains("clamped")),
        "{:?}",
        l.warnings
    );
    assert!(l.desc.materials.iter().any(|m| matches!(
        m,
        Material::Diffuse(material::Diffuse { reflectance }) if *reflectance == Rgb::new(1.0, 0.5, 1.0)
    )));
}

/// pbrt-v4 exposes the image by the film's iso / 100 times the shutter's seconds (measured with
/// pbrt-v4 itself: iso 150 renders 1.5x, iso 400 with shutter 0..0.5 2x, shutter 0.2..0.7
/// 0.5x the iso-100, 0..1 image): every emitter takes the factor, and a note says so.
#[test]
fn the_films_iso_and_the_shutter_expose_every_emitter() {
    let scene = |film: &str, camera: &str| {
        load(&format!(
            r#"Film "rgb" "integer xresolution" 8 "integer yresolution" 8 {film}
            Camera "perspective" "float fov" 45 {camera}
            WorldBegin
            LightSource "point" "point3 from" [0 0 1] "rgb I" [1 2 3]
            LightSource "spot" "rgb I" [1 1 1] "point3 from" [0 0 5] "point3 to" [0 0 0]
            LightSource "distant" "point3 from" [0 0 1] "point3 to" [0 0 0] "rgb L" [2 2 2]
            LightSource "infinite" "rgb L" [0.1 0.2 0.3]
            AttributeBegin
              AreaLightSource "diffuse" "rgb L" [1 2 3]
              Shape "disk" "float radius" 2
            AttributeEnd"#
        ))
        .expect("load")
    };
    let emitters = |s: &pbrt::Loaded| -> Vec<Rgb> {
        let lights = s.desc.lights.iter().map(|l| match l {
            LightDesc::Point { intensity, .. } | LightDesc::Spot { intensity, .. } => *intensity,
            LightDesc::Distant { irradiance, .. } => *irradiance,
            LightDesc::Environment(EnvironmentDesc::Constant(l)) => *l,
            other => panic!("{other:?}"),
        });
        let areas = s
            .desc
            .shapes
            .iter()
            .filter_map(|s| s.emission.map(|e| e.radiance));
        lights.chain(areas).collect()
    };
    let plain = scene("", "");
    assert!(plain.notes.is_empty());
    for (film, camera, k) in [
        (r#""float iso" 150"#, "", 1.5),
        (
            r#""float iso" 400"#,
            r#""float shutteropen" 0 "float shutterclose" 0.5"#,
            2.0,
        ),
        (
            "",
            r#""float shutteropen" 0.2 "float shutterclose" 0.7"#,
            0.5,
        ),
        (r#""float iso" 100"#, r#""float shutterclose" 1"#, 1.0),
    ] {
        let s = scene(film, camera);
        for (e, p) in emitters(&s).into_iter().zip(emitters(&plain)) {
            let off = (e - p * k).to_array().map(f32::abs);
            assert!(
                off.iter().all(|&d| d < 1e-6),
                "{film} {camera}: {e:?} {p:?}"
            );
        }
        let noted = s
            .notes
            .iter()
            .any(|n| n.what.contains(&format!("expose the image {k}x")));
        assert_eq!(noted, k != 1.0, "{film} {camera}: {:?}", s.notes);
    }
    let Err(e) = load(r#"Film "rgb" "float iso" -3"#) else {
        panic!("a negative iso loads")
    };
    assert!(e.contains("iso must be positive"), "{e}");
    // A named sensor is balanced as pbrt-v4 balances it: at its whitebalance, or 6500 K.
    for (film, balance) in [(r#""float whitebalance" 5000"#, 5000.0), ("", 6500.0)] {
        let s = load(&format!(
            r#"Film "rgb" "string sensor" "canon_eos_100d" {film}"#
        ))
        .expect("load");
        assert!(
            s.warnings.iter().any(|w| w
                .what
                .contains("the camera's own colour response needs a spectral renderer")),
            "{:?}",
            s.warnings
        );
        assert_eq!(s.desc.camera.white_balance, Some(balance), "{film}");
    }
    let Err(e) = load(r#"Film "rgb" "string sensor" "leica_m3""#) else {
        panic!("an unknown sensor loads")
    };
    assert!(e.contains("unknown sensor \"leica_m3\""), "{e}");
    assert!(e.contains(".pbrt:"), "the error names file:line: {e}");
}

#[test]
fn the_films_white_balance_goes_to_the_camera() {
    let s = load(r#"Film "rgb" "float whitebalance" 3500"#).expect("load");
    assert_eq!(s.desc.camera.white_balance, Some(3500.0));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let s = load(r#"Film "rgb" "float whitebalance" 0"#).expect("load");
    assert_eq!(s.desc.camera.white_balance, None, "0 is pbrt-v4's none");
    let Err(e) = load(r#"Film "rgb" "float whitebalance" -10"#) else {
        panic!("a negative white balance loads")
    };
    assert!(
        e.contains("whitebalance must be a colour temperature"),
        "{e}"
    );
    assert!(e.contains(".pbrt:"), "the error names file:line: {e}");
}

/// An area light's "power" is each triangle's, as pbrt-v4 makes every triangle of a mesh a
/// light of its own: a quad of two equal triangles stays one emitter whose triangles each
/// emit the power; a mesh of unequal triangles becomes one emitter per triangle, its
/// degenerate triangles dropped.
#[test]
fn area_light_power_is_each_triangles() {
    let s = load(
        r#"WorldBegin
        AttributeBegin
        AreaLightSource "diffuse" "rgb L" [1 1 1] "float power" 10
        Shape "trianglemesh" "point3 P" [0 0 0  2 0 0  2 1 0  0 1 0] "integer indices" [0 1 2  0 2 3]
        Shape "trianglemesh" "point3 P" [0 0 1  1 0 1  0 1 1  3 0 1  1 0 1] "integer indices" [0 1 2  0 3 2  0 1 4]
        AttributeEnd"#,
    )
    .expect("load");
    let emitters: Vec<_> = s
        .desc
        .shapes
        .iter()
        .filter(|s| s.emission.is_some())
        .collect();
    assert_eq!(emitters.len(), 3, "one quad, two of the three triangles");
    let each = |shape: &fenestra_scene::Shape, triangle_area: f32| {
        let e = shape.emission.expect("emitter");
        e.radiance.r * std::f32::consts::PI * triangle_area
    };
    assert!((each(emitters[0], 1.0) - 10.0).abs() < 1e-4);
    for shape in &emitters[1..] {
        let a = shape.area();
        assert!(a > 0.0 && (each(shape, a) - 10.0).abs() < 1e-4, "{a}");
    }
}
