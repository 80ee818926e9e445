//! Materials and their textures (float, scale, mix, checkerboard, image, bump and normal maps, coated layers) and spectra, as pbrt-v4 defines them.

use super::*;

#[test]
fn materials_lights_and_render_settings() {
    let s = load(
        r#"Film "rgb" "integer xresolution" 64 "integer yresolution" 32 "string filename" "x.exr"
        Sampler "halton" "integer pixelsamples" 128
        Integrator "volpath" "integer maxdepth" 3
        Camera "perspective" "float fov" 45
        WorldBegin
        LightSource "point" "point3 from" [0 0 1] "blackbody I" 3000 "float power" 100
        LightSource "spot" "rgb I" [1 1 1] "point3 from" [0 0 5] "point3 to" [0 0 0] "float coneangle" 20 "float conedeltaangle" 5
        LightSource "distant" "point3 from" [0 0 1] "point3 to" [0 0 0] "rgb L" [2 2 2]
        LightSource "infinite" "rgb L" [0.1 0.2 0.3] "point3 portal" [0 0 1  1 0 1  1 1 1  0 1 1]
        Material "conductor" "spectrum eta" "metal-Au-eta" "spectrum k" "metal-Au-k" "float roughness" 0.04
        Shape "sphere"
        Material "conductor" "rgb reflectance" [0.9 0.5 0.1]
        Shape "sphere"
        Material "dielectric" "spectrum eta" "glass-BK7"
        Shape "sphere"
        Material "thindielectric"
        Shape "sphere"
        Material "coateddiffuse" "rgb reflectance" [0.5 0.5 0.5] "float roughness" 0.01
        Shape "sphere"
        AttributeBegin
          AreaLightSource "diffuse" "rgb L" [1 2 3] "float power" 10 "bool twosided" true
          Shape "disk" "float radius" 2
        AttributeEnd"#,
    )
    .expect("load");
    assert!(
        s.warnings.is_empty(),
        "{:?}",
        s.warnings
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
    );
    let d = &s.desc;
    assert_eq!(
        (
            d.defaults.width,
            d.defaults.height,
            d.defaults.spp,
            d.defaults.max_depth
        ),
        (64, 32, 128, 4)
    );
    let LightDesc::Point { intensity, .. } = d.lights[0] else {
        panic!("point")
    };
    assert!((intensity.luminance() - 100.0 / (4.0 * std::f32::consts::PI)).abs() < 1e-3);
    assert!(intensity.r > intensity.b, "3000 K is warm");
    assert!(
        matches!(d.lights[1], LightDesc::Spot { direction, cone_angle, falloff_start, .. } if direction == -Vec3::Z && cone_angle == 20.0 && falloff_start == 15.0)
    );
    assert!(matches!(d.lights[2], LightDesc::Distant { direction, .. } if direction == -Vec3::Z));
    assert!(
        matches!(d.lights[3], LightDesc::Environment(EnvironmentDesc::Constant(l)) if l == Rgb::new(0.1, 0.2, 0.3))
    );
    assert_eq!(d.portals.len(), 1);
    let mats: Vec<&Material> = d.shapes.iter().map(|s| &d.materials[s.material]).collect();
    assert!(
        matches!(mats[0], Material::RoughConductor(material::RoughConductor { alpha_x, eta, .. }) if (alpha_x - 0.2).abs() < 1e-6 && eta.b > eta.r)
    );
    assert!(
        matches!(mats[1], Material::Mirror(material::Mirror { reflectance }) if (reflectance.r - 0.9).abs() < 1e-3 && (reflectance.b - 0.1).abs() < 1e-3)
    );
    assert!(
        matches!(mats[2], Material::Dielectric(material::Dielectric { eta }) if (eta - 1.5168).abs() < 1e-4)
    );
    assert!(
        matches!(mats[3], Material::ThinDielectric(material::ThinDielectric { eta }) if *eta == 1.5)
    );
    assert!(
        matches!(mats[4], Material::CoatedDiffuse(material::CoatedDiffuse { eta, .. }) if *eta == 1.5)
    );
    // coatedconductor, as the killeroo-coated-gold scene writes it.
    let gold = load(
        r#"WorldBegin
        Material "coatedconductor" "spectrum conductor.eta" "metal-Au-eta"
            "spectrum conductor.k" "metal-Au-k" "float interface.roughness" 0.04
            "float conductor.roughness" 0.01
        Shape "sphere""#,
    )
    .expect("coatedconductor");
    assert!(gold.warnings.is_empty(), "{:?}", gold.warnings);
    assert!(matches!(
        gold.desc.materials[0],
        Material::CoatedConductor(material::CoatedConductor { interface_eta, interface_alpha, alpha_x, eta, .. })
            if interface_eta == 1.5 && (interface_alpha - 0.2).abs() < 1e-6
                && (alpha_x - 0.1).abs() < 1e-6 && eta.b > eta.r
    ));
    let e = d.shapes[5].emission.expect("emitter");
    assert!(e.two_sided);
    // pbrt-v4 scales an RGB emission as given: radiance = L power / (2 pi area).
    let l = e.radiance * (std::f32::consts::PI * 2.0 * d.shapes[5].area() / 10.0);
    assert!(
        (l - Rgb::new(1.0, 2.0, 3.0)).max_component().abs() < 1e-4,
        "{l:?}"
    );
    assert!(
        (Rgb::new(1.0, 2.0, 3.0) - l).max_component().abs() < 1e-4,
        "{l:?}"
    );
}

#[test]
fn float_textures_vary_conductor_roughness_and_give_their_average_elsewhere() {
    // The official crown scene stopped at "roughness has type texture but float is expected".
    let dir = scratch("float-textures");
    let mut grey = fenestra_core::image::Image::new(2, 1);
    grey.set(0, 0, Rgb::splat(0.2));
    grey.set(1, 0, Rgb::splat(0.4));
    grey.write_exr(&dir.join("rough.exr"), &Default::default())
        .expect("exr");
    std::fs::write(
        dir.join("s.pbrt"),
        r#"WorldBegin
        Texture "quarter" "float" "constant" "float value" 0.25
        Texture "map" "float" "imagemap" "string filename" "rough.exr"
        Texture "mixed" "float" "mix" "float amount" 0.5
        Material "conductor" "texture roughness" "quarter"
        Shape "sphere"
        Material "conductor" "texture uroughness" "map" "float vroughness" 0.3
        Shape "sphere"
        Material "dielectric" "texture roughness" "mixed"
        Shape "sphere""#,
    )
    .expect("scene");
    let s = pbrt::load(&dir.join("s.pbrt"), false).expect("lenient");
    let alphas = |m: &Material| match *m {
        Material::RoughConductor(material::RoughConductor {
            alpha_x, alpha_y, ..
        }) => (alpha_x, alpha_y),
        ref other => panic!("rough conductor expected, found {other:?}"),
    };
    let (ax, ay) = alphas(&s.desc.materials[0]);
    assert!((ax - 0.5).abs() < 1e-6 && (ay - 0.5).abs() < 1e-6);
    // An image on a conductor's roughness is looked up at each hit (its mean stands for it
    // where one value is needed); the constant v roughness stays.
    let (ax, ay) = alphas(&s.desc.materials[1]);
    assert!((ax - 0.3f32.sqrt()).abs() < 1e-6 && (ay - 0.3f32.sqrt()).abs() < 1e-6);
    let mapped = |m: &Material| match m {
        Material::RoughConductor(material::RoughConductor {
            roughness: Some(map),
            alpha_x,
            alpha_y,
            ..
        }) => [0.25, 0.75].map(|u| map.alphas(Vec2::new(u, 0.5), (*alpha_x, *alpha_y))),
        other => panic!("textured roughness expected, found {other:?}"),
    };
    let at = mapped(&s.desc.materials[1]);
    let close = |a: (f32, f32), b: (f32, f32)| (a.0 - b.0).abs() < 1e-6 && (a.1 - b.1).abs() < 1e-6;
    assert!(close(at[0], (0.2f32.sqrt(), 0.3f32.sqrt())), "{at:?}");
    assert!(close(at[1], (0.4f32.sqrt(), 0.3f32.sqrt())), "{at:?}");
    assert!(matches!(
        s.desc.materials[2],
        Material::Dielectric(material::Dielectric { .. })
    ));
    let w: Vec<String> = s.warnings.iter().map(ToString::to_string).collect();
    for says in [
        "float texture for \"roughness\" (its average, 0.25, is used)",
        "float Texture class \"mix\"",
        "float texture for \"roughness\" (the default is used)",
    ] {
        assert!(w.iter().any(|w| w.contains(says)), "{says}: {w:?}");
    }
    assert!(!w.iter().any(|w| w.contains("uroughness")), "{w:?}");
    // Exported and read back, the texture varies the same way.
    let path = dir.join("export.pbrt");
    pbrt::export::write(&s.desc, &path).expect("export");
    let t = pbrt::load(&path, false).expect("re-read").desc;
    let back = mapped(&t.materials[1]);
    assert!(
        close(back[0], at[0]) && close(back[1], at[1]),
        "{back:?} vs {at:?}"
    );
    let e = pbrt::load(&dir.join("s.pbrt"), true)
        .err()
        .expect("strict refuses it")
        .to_string();
    assert!(e.contains("unsupported in strict mode"), "{e}");
    let e = load("WorldBegin\nMaterial \"conductor\" \"texture roughness\" \"none\"")
        .err()
        .expect("unknown");
    assert!(e.contains("2:1: unknown float texture \"none\""), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn spectrum_files_are_read_relative_to_the_scene_file() {
    // killeroo-gold stopped at "spectrum files are not supported".
    let dir = scratch("spd");
    std::fs::create_dir_all(dir.join("spds")).expect("dir");
    std::fs::write(dir.join("spds/two.spd"), "# flat\n380 2\n780 2\n").expect("spd");
    std::fs::write(
        dir.join("s.pbrt"),
        "WorldBegin\nMaterial \"conductor\" \"spectrum eta\" \"spds/two.spd\" \"spectrum k\" \"spds/two.spd\"\n\
         Shape \"sphere\"\n",
    )
    .expect("scene");
    let s = pbrt::load(&dir.join("s.pbrt"), true).expect("load");
    // The file is one of the scene's inputs (no output may replace it).
    assert!(s.files.contains(&dir.join("spds/two.spd")), "{:?}", s.files);
    // A smooth conductor of eta = k = 2: F0 = ((2-1)^2 + 4) / ((2+1)^2 + 4) = 5/13.
    let Material::Mirror(material::Mirror { reflectance }) = s.desc.materials[0] else {
        panic!("mirror")
    };
    assert!((reflectance.g - 5.0 / 13.0).abs() < 1e-3, "{reflectance:?}");
    std::fs::remove_file(dir.join("spds/two.spd")).expect("remove");
    let e = pbrt::load(&dir.join("s.pbrt"), true)
        .err()
        .expect("missing file")
        .to_string();
    assert!(
        e.contains("s.pbrt:2:") && e.contains("cannot read spectrum file"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn scale_and_mix_textures() {
    // The killeroo scenes' floors are a "scale" of an image; both used to become grey.
    let dir = scratch("scale-mix");
    let mut tex = fenestra_core::image::Image::new(2, 1);
    tex.set(0, 0, Rgb::new(1.0, 0.0, 0.0));
    tex.set(1, 0, Rgb::new(0.0, 0.0, 1.0));
    tex.write_exr(&dir.join("t.exr"), &Default::default())
        .expect("tex");
    std::fs::write(
        dir.join("s.pbrt"),
        r#"WorldBegin
        Texture "grid" "spectrum" "imagemap" "string filename" "t.exr"
        Texture "half" "spectrum" "scale" "texture tex" "grid" "float scale" 0.5
        Texture "value" "spectrum" "scale" "rgb tex" [0.2 0.4 0.6] "float scale" 1.5
        Texture "mixed" "spectrum" "mix" "rgb tex1" [1 0 0] "rgb tex2" [0 0 1] "float amount" 0.25
        Texture "blend" "spectrum" "mix" "texture tex1" "grid" "rgb tex2" [0 1 0]
        Material "diffuse" "texture reflectance" "half"
        Shape "sphere"
        Material "diffuse" "texture reflectance" "value"
        Shape "sphere"
        Material "diffuse" "texture reflectance" "mixed"
        Shape "sphere"
        Material "diffuse" "texture reflectance" "blend"
        Shape "sphere""#,
    )
    .expect("scene");
    let s = pbrt::load(&dir.join("s.pbrt"), false).expect("load");
    let Material::TexturedDiffuse(material::TexturedDiffuse { texture }) = &s.desc.materials[0]
    else {
        panic!("a scaled image stays an image")
    };
    assert_eq!(
        texture.lookup(Vec2::new(0.25, 0.5)),
        Rgb::new(0.5, 0.0, 0.0)
    );
    let reflectance = |m: &Material| match *m {
        Material::Diffuse(material::Diffuse { reflectance }) => reflectance,
        ref other => panic!("diffuse expected, found {other:?}"),
    };
    let close = |a: Rgb, b: Rgb| (a - b).map(f32::abs).max_component() < 1e-6;
    assert!(close(
        reflectance(&s.desc.materials[1]),
        Rgb::new(0.3, 0.6, 0.9)
    ));
    assert!(close(
        reflectance(&s.desc.materials[2]),
        Rgb::new(0.75, 0.0, 0.25)
    ));
    // An image in a mix: the means are mixed, and said.
    assert!(close(
        reflectance(&s.desc.materials[3]),
        Rgb::new(0.25, 0.5, 0.25)
    ));
    let w: Vec<String> = s.warnings.iter().map(ToString::to_string).collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("mix of image textures"), "{w:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn checkerboard_mix_and_diffuse_transmission_as_pbrt_v4_defines_them() {
    let s = load(
        r#"WorldBegin
        Texture "checks" "spectrum" "checkerboard" "rgb tex1" [1 0 0] "rgb tex2" [0 0 1]
            "float uscale" 4 "float vscale" 2 "float udelta" 0.5
        MakeNamedMaterial "red" "string type" "diffuse" "rgb reflectance" [0.8 0.1 0.1]
        MakeNamedMaterial "leaf" "string type" "diffusetransmission"
            "rgb reflectance" [0.2 0.5 0.1] "rgb transmittance" [0.1 0.4 0.1] "float scale" 2
        MakeNamedMaterial "both" "string type" "mix" "string materials" ["red" "leaf"]
            "float amount" 0.3
        Material "diffuse" "texture reflectance" "checks"
        Shape "sphere"
        NamedMaterial "both"
        Shape "sphere""#,
    )
    .expect("load");
    // The named materials in order, then the checks.
    let [red, leaf, both, checks] = [0, 1, 2, 3];
    let Material::TexturedDiffuse(material::TexturedDiffuse { texture }) =
        &s.desc.materials[checks]
    else {
        panic!("a checkerboard is a texture")
    };
    // pbrt-v4: tex1 where floor(s) + floor(t) is even, s = 4u + 0.5, t = 2v (check centres,
    // away from the edges the lookup blurs).
    for (u, v) in [
        (0.0, 0.25),
        (0.1, 0.25),
        (0.3, 0.9),
        (0.55, 0.6),
        (0.9, 0.1),
        (-0.3, -0.7),
    ] {
        let (s_, t_): (f32, f32) = (4.0 * u + 0.5, 2.0 * v);
        let even = (s_.floor() + t_.floor()) as i64 % 2 == 0;
        let want = if even {
            Rgb::new(1.0, 0.0, 0.0)
        } else {
            Rgb::new(0.0, 0.0, 1.0)
        };
        assert_eq!(texture.lookup(Vec2::new(u, v)), want, "uv ({u}, {v})");
    }
    assert!(matches!(
        s.desc.materials[red],
        Material::Diffuse(material::Diffuse { .. })
    ));
    assert!(matches!(
        s.desc.materials[leaf],
        Material::DiffuseTransmission(material::DiffuseTransmission { reflectance, transmittance })
            if (reflectance - Rgb::new(0.4, 1.0, 0.2)).max_component().abs() < 1e-6
            && (transmittance - Rgb::new(0.2, 0.8, 0.2)).max_component().abs() < 1e-6
    ));
    assert!(matches!(
        s.desc.materials[both],
        Material::Mix(material::Mix { materials: [0, 1], amount }) if amount == 0.3
    ));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    // The exporter writes them so that they read back the same.
    let dir = scratch("mix-export");
    let path = dir.join("e.pbrt");
    pbrt::export::write(&s.desc, &path).expect("export");
    let t = pbrt::load(&path, true).expect("re-read").desc;
    assert_eq!(
        format!("{:?}", &t.materials[red..=both]),
        format!("{:?}", &s.desc.materials[red..=both])
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn image_textures_and_environments() {
    let dir = scratch("images");
    let mut tex = fenestra_core::image::Image::new(2, 1);
    tex.set(0, 0, Rgb::new(1.0, 0.0, 0.0));
    tex.set(1, 0, Rgb::new(0.0, 0.0, 1.0));
    tex.write_exr(&dir.join("t.exr"), &Default::default())
        .expect("tex");
    let mut sky = fenestra_core::image::Image::new(64, 64);
    for y in 0..64 {
        for x in 0..64 {
            sky.set(x, y, Rgb::splat(0.5));
        }
    }
    sky.write_exr(&dir.join("sky.exr"), &Default::default())
        .expect("sky");
    std::fs::write(
        dir.join("s.pbrt"),
        r#"WorldBegin
        LightSource "infinite" "string filename" "sky.exr" "float illuminance" 10
        Texture "checks" "spectrum" "imagemap" "string filename" "t.exr"
        Material "diffuse" "texture reflectance" "checks"
        Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "point2 uv" [0 0 1 0 0 1]"#,
    )
    .expect("scene");
    let s = pbrt::load(&dir.join("s.pbrt"), true).expect("load");
    let Material::TexturedDiffuse(material::TexturedDiffuse { texture }) = &s.desc.materials[0]
    else {
        panic!("textured")
    };
    assert_eq!(
        texture.lookup(Vec2::new(0.25, 0.5)),
        Rgb::new(1.0, 0.0, 0.0)
    );
    // A coated base keeps its texture (looked up at each hit), without a warning.
    let coated = pbrt::load_bytes(
        br#"WorldBegin
        Texture "checks" "spectrum" "imagemap" "string filename" "t.exr"
        Material "coateddiffuse" "texture reflectance" "checks" "float roughness" 0.1
        Shape "sphere""#,
        &dir.join("c.pbrt"),
        true,
    )
    .expect("strict: nothing approximated");
    assert!(matches!(
        &coated.desc.materials[0],
        Material::CoatedDiffuse(material::CoatedDiffuse { texture: Some(t), .. }) if t.lookup(Vec2::new(0.75, 0.5)) == Rgb::new(0.0, 0.0, 1.0)
    ));
    let LightDesc::Environment(EnvironmentDesc::Image { image, scale, .. }) = &s.desc.lights[0]
    else {
        panic!("image environment")
    };
    assert_eq!((image.width, image.height), (128, 64));
    // pbrt-v4 counts half the map's illuminance (each upper pixel weighted 2pi / N, half its
    // solid angle), so "illuminance" 10 makes the map's true illuminance pi L scale about 20
    // (to the map's discretisation of cos theta over its pixel centres).
    let true_illuminance = std::f32::consts::PI * 0.5 * scale.r;
    assert!(
        (true_illuminance / 20.0 - 1.0).abs() < 0.01,
        "{true_illuminance} ({scale:?})"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bump_and_normal_maps_and_the_layers_of_coated_materials() {
    let dir = scratch("relief");
    let mut height = fenestra_core::image::Image::new(2, 1);
    height.set(0, 0, Rgb::splat(0.0));
    height.set(1, 0, Rgb::splat(1.0));
    height
        .write_exr(&dir.join("h.exr"), &Default::default())
        .expect("height");
    // An 8-bit normal map: 128 is 0.502 as stored (pbrt-v4 reads normal maps linearly), not
    // the 0.216 an sRGB decoding would give.
    let mut normals = fenestra_core::image::Image::new(2, 2);
    let stored = |byte: f32| fenestra_core::image::srgb_to_linear(byte / 255.0);
    for (x, y) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
        normals.set(x, y, Rgb::new(stored(128.0), stored(128.0), 1.0));
    }
    normals
        .write_png(&dir.join("n.png"), Some(0.0))
        .expect("normals");
    std::fs::write(
        dir.join("s.pbrt"),
        r#"WorldBegin
        Texture "h" "float" "imagemap" "string filename" "h.exr" "float scale" 0.1
        Material "diffuse" "texture displacement" "h"
        Shape "sphere"
        Material "conductor" "string normalmap" "n.png"
        Shape "sphere"
        Material "coateddiffuse" "float thickness" 0.2 "rgb albedo" [0.5 0.4 0.3] "float g" 0.3 "integer maxdepth" 20 "integer nsamples" 2
        Shape "sphere""#,
    )
    .expect("scene");
    let s = pbrt::load(&dir.join("s.pbrt"), true).expect("strict: nothing approximated");
    let relief = |i: usize| s.desc.shapes[i].relief.as_deref();
    let Some(material::Relief::Bump(bump)) = relief(0) else {
        panic!("bump map")
    };
    assert!((bump.displacement.lookup(Vec2::new(0.75, 0.5)).r - 0.1).abs() < 1e-6);
    let Some(material::Relief::Normals(map)) = relief(1) else {
        panic!("normal map")
    };
    assert!((map.texture.lookup(Vec2::new(0.5, 0.5)).r - 128.0 / 255.0).abs() < 1e-6);
    assert!(relief(2).is_none());
    let Material::CoatedDiffuse(coated) = &s.desc.materials[2] else {
        panic!("coated")
    };
    assert_eq!(
        coated.layers,
        material::Layers {
            thickness: 0.2,
            albedo: Rgb::new(0.5, 0.4, 0.3),
            g: 0.3,
            max_depth: 20,
            samples: 2
        }
    );
    let err = pbrt::load_bytes(
        br#"WorldBegin
        Material "diffuse" "texture displacement" "nowhere""#,
        &dir.join("e.pbrt"),
        true,
    )
    .err()
    .expect("an unknown texture is an error");
    assert!(
        err.to_string().contains("e.pbrt:2") && err.to_string().contains("\"nowhere\""),
        "{err}"
    );
    let err = pbrt::load_bytes(
        br#"WorldBegin
        Material "coateddiffuse" "float g" 1.5
        Shape "sphere""#,
        &dir.join("g.pbrt"),
        true,
    )
    .err()
    .expect("g outside (-1, 1) is an error");
    assert!(
        err.to_string().contains("g 1.5 must lie in (-1, 1)"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A conductor's reflectance given as a texture (pbrt-v4 takes one; fenestra's exports of
/// textured glTF metals write one, which fenestra itself refused to read back): the image's
/// mean colour, warned.
#[test]
fn a_conductors_reflectance_texture_gives_its_mean_colour() {
    let dir = scratch("conductor-texture");
    let mut img = fenestra_core::image::Image::new(2, 1);
    img.set(0, 0, Rgb::new(0.2, 0.4, 0.6));
    img.set(1, 0, Rgb::new(0.6, 0.4, 0.2));
    img.write_exr(&dir.join("metal.exr"), &Default::default())
        .expect("exr");
    std::fs::write(
        dir.join("s.pbrt"),
        r#"WorldBegin
        Texture "m" "spectrum" "imagemap" "string filename" "metal.exr"
        Material "conductor" "texture reflectance" "m" "float roughness" 0.3
        Shape "sphere"
        Material "conductor" "rgb reflectance" [0.4 0.4 0.4] "float roughness" 0.3
        Shape "sphere""#,
    )
    .expect("scene");
    let s = pbrt::load(&dir.join("s.pbrt"), false).expect("lenient");
    let optics = |m: &Material| match *m {
        Material::RoughConductor(material::RoughConductor { eta, k, .. }) => (eta, k),
        ref other => panic!("rough conductor expected, found {other:?}"),
    };
    let (textured, plain) = (optics(&s.desc.materials[0]), optics(&s.desc.materials[1]));
    assert!(
        (textured.1 - plain.1).max_component().abs() < 1e-5,
        "{textured:?} {plain:?}"
    );
    assert_eq!(textured.0, Rgb::ONE);
    assert!(s
        .warnings
        .iter()
        .any(|w| w.to_string().contains("its mean colour is used")));
}
