//! Denoising features (albedo and normal) against what a wall seen straight, in a mirror,
//! through a pane and as a texture must give; read off the path tracer's own paths and by
//! the drivers' feature samples alike; the same for any thread count and for a render
//! split by sample ranges.

use fenestra_core::image::Image;
use fenestra_core::{Rgb, Vec3};
use fenestra_render::bsdf::ThinDielectric;
use fenestra_render::features::{feature_sample, FeaturePixel, FEATURE_SAMPLES};
use fenestra_render::integrator::{af_hf, PathOptions};
use fenestra_render::light::LightSelection;
use fenestra_render::sample_context::SampleContext;
use fenestra_render::{render, Film, RenderControl, RenderScene, RenderSettings};
use fenestra_scene::material::{Diffuse, Mirror, TexturedDiffuse, ThinDielectric as Pane};
use fenestra_scene::texture::ImageTexture;
use fenestra_scene::TriangleMesh;
use fenestra_scene::{
    Backend, Camera, Material, RenderDefaults, Scene, SceneDesc, Shape, ShapeKind,
};
use std::sync::Arc;

const SIZE: u32 = 32;
const WALL: Rgb = Rgb::new(0.2, 0.5, 0.8);

/// A scene seen from the origin along +y (a 20-degree view): `shapes` with `materials`.
fn scene(shapes: Vec<Shape>, materials: Vec<Material>) -> RenderScene {
    let desc = SceneDesc {
        name: "features".into(),
        shapes,
        materials,
        lights: Vec::new(),
        camera: Camera::look_at(Vec3::ZERO, Vec3::Y, Vec3::Z, 20.0).expect("camera"),
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    };
    RenderScene::new(Scene::build(desc, Backend::default()).expect("scene"))
}

/// A 4 m square facing `normal`, centred at `centre`.
fn square(centre: Vec3, normal: Vec3, material: usize) -> Shape {
    let (u, v) = if normal.y.abs() > 0.5 {
        (Vec3::X * 2.0, Vec3::Z * 2.0)
    } else {
        (Vec3::Y * 2.0, Vec3::Z * 2.0)
    };
    // TriangleMesh::quad faces hu x hv.
    let (u, v) = if u.cross(v).dot(normal) > 0.0 {
        (u, v)
    } else {
        (v, u)
    };
    Shape::new(ShapeKind::Mesh(TriangleMesh::quad(centre, u, v)), material)
}

fn diffuse(c: Rgb) -> Material {
    Material::Diffuse(Diffuse { reflectance: c })
}

/// The film of an af_hf render of `scene` with features, samples `first..first + spp`.
fn film_of(scene: &RenderScene, first: u32, spp: u32) -> Film {
    let mut film = Film::new(SIZE, SIZE).with_features();
    let settings = RenderSettings {
        first_sample: first,
        spp,
        time_limit: None,
        seed: 3,
    };
    let mut integrator = af_hf(PathOptions::default(), LightSelection::Power);
    render(
        &mut integrator,
        scene,
        &mut film,
        &settings,
        &RenderControl::unattended(),
    )
    .expect("render");
    film
}

/// The features the drivers' own feature samples give (for integrators that do not read
/// them off their paths), as a film's.
fn sampled_features(scene: &RenderScene) -> Vec<FeaturePixel> {
    let mut out = vec![FeaturePixel::default(); (SIZE * SIZE) as usize];
    for (i, f) in out.iter_mut().enumerate() {
        let (x, y) = (i as u32 % SIZE, i as u32 / SIZE);
        for index in 0..FEATURE_SAMPLES {
            let ctx = SampleContext {
                x,
                y,
                width: SIZE,
                height: SIZE,
                block: 0,
                pass: 0,
                index,
            };
            f.add(&feature_sample(scene, &ctx, 3));
        }
    }
    out
}

fn images(features: &[FeaturePixel]) -> (Image, Image) {
    let mut film = Film::new(SIZE, SIZE).with_features();
    film.features.copy_from_slice(features);
    film.feature_images().expect("features")
}

/// Both ways of taking features, as (albedo, normal) images.
fn both(scene: &RenderScene) -> [(&'static str, (Image, Image)); 2] {
    let film = film_of(scene, 0, 16);
    assert!(film.features.iter().all(|f| f.count == FEATURE_SAMPLES));
    [
        (
            "read off the paths",
            film.feature_images().expect("features"),
        ),
        ("feature samples", images(&sampled_features(scene))),
    ]
}

fn assert_close(what: &str, got: [f32; 3], want: [f32; 3], tolerance: f32) {
    let off = (0..3).map(|c| (got[c] - want[c]).abs()).fold(0.0, f32::max);
    assert!(off <= tolerance, "{what}: {got:?}, expected {want:?}");
}

#[test]
fn a_wall_seen_straight_has_its_reflectance_and_its_normal() {
    let scene = scene(
        vec![square(Vec3::Y * 3.0, -Vec3::Y, 0)],
        vec![diffuse(WALL)],
    );
    for (how, (albedo, normal)) in both(&scene) {
        for (a, n) in albedo.pixels.iter().zip(&normal.pixels) {
            // Fixed point of 2^-24 per sample.
            assert_close(how, a.to_array(), WALL.to_array(), 1e-6);
            assert_close(how, n.to_array(), [0.0, -1.0, 0.0], 1e-6);
        }
    }
}

#[test]
fn a_wall_seen_in_a_mirror_has_the_reflectance_of_both_and_its_own_normal() {
    // A mirror ahead facing the camera, the wall behind it facing the mirror.
    let shapes = vec![
        square(Vec3::Y * 3.0, -Vec3::Y, 0),
        square(-Vec3::Y * 1.0, Vec3::Y, 1),
    ];
    let mirror = Material::Mirror(Mirror {
        reflectance: Rgb::splat(0.9),
    });
    let scene = scene(shapes, vec![mirror, diffuse(WALL)]);
    for (how, (albedo, normal)) in both(&scene) {
        for (a, n) in albedo.pixels.iter().zip(&normal.pixels) {
            assert_close(how, a.to_array(), (WALL * 0.9).to_array(), 2e-6);
            assert_close(how, n.to_array(), [0.0, 1.0, 0.0], 1e-6);
        }
    }
}

#[test]
fn a_wall_behind_a_pane_is_seen_through_its_transmittance() {
    // The pane's reflection sees nothing (no environment): albedo 0, no normal.
    let shapes = vec![
        square(Vec3::Y * 2.0, -Vec3::Y, 0),
        square(Vec3::Y * 3.0, -Vec3::Y, 1),
    ];
    let pane = Material::ThinDielectric(Pane { eta: 1.5 });
    let scene = scene(shapes, vec![pane, diffuse(WALL)]);
    // Nearly normal incidence over the 20-degree view: R' within 0.1% of its value at 0.
    let r = ThinDielectric { eta: 1.5 }.reflectance(1.0) as f64;
    let samples = f64::from(SIZE * SIZE * FEATURE_SAMPLES);
    // Each sample sees the wall or nothing: a binomial share.
    let tolerance = 4.0 * (r * (1.0 - r) / samples).sqrt() + 1e-3 * r;
    for (how, (albedo, normal)) in both(&scene) {
        let n = albedo.pixels.len() as f64;
        let seen = albedo
            .pixels
            .iter()
            .map(|a| f64::from(a.g) / 0.5)
            .sum::<f64>()
            / n;
        let facing = normal.pixels.iter().map(|v| -f64::from(v.g)).sum::<f64>() / n;
        for (share, what) in [(seen, "albedo"), (facing, "normal")] {
            assert!(
                (share - (1.0 - r)).abs() < tolerance,
                "{how}: the wall's {what} seen {share:.5} of the time, the pane transmits {:.5}",
                1.0 - r
            );
        }
        // Every sample saw the wall or nothing: albedo in proportion to the wall's.
        for a in &albedo.pixels {
            let scaled = *a * (0.5 / a.g.max(1e-9));
            assert_close(how, scaled.to_array(), WALL.to_array(), 1e-5);
        }
    }
}

#[test]
fn a_textured_wall_has_its_texture_as_albedo() {
    // Four uniform 16x16-texel blocks; the view sees the middle half of the wall, so each
    // quarter of the image lies on one block.
    let colours = [
        Rgb::new(0.9, 0.1, 0.1),
        Rgb::new(0.1, 0.8, 0.2),
        Rgb::new(0.2, 0.3, 0.7),
        Rgb::new(0.6, 0.6, 0.1),
    ];
    let mut texels = Image::new(32, 32);
    for y in 0..32 {
        for x in 0..32 {
            texels.set(x, y, colours[(y / 16) * 2 + x / 16]);
        }
    }
    let texture = ImageTexture::new(Arc::new(texels), "blocks.png".into());
    let textured = Material::TexturedDiffuse(TexturedDiffuse {
        texture: Arc::new(texture),
    });
    // At 5.67 m the 20-degree view spans 2 m: the middle half of the 4 m wall.
    let distance = 1.0 / (10f32.to_radians()).tan();
    let scene = scene(
        vec![square(Vec3::Y * distance, -Vec3::Y, 0)],
        vec![textured],
    );
    for (how, (albedo, _)) in both(&scene) {
        let mut seen = Vec::new();
        for (qx, qy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            // The quarter's pixels away from the blocks' borders (bilinear filtering blends
            // within half a texel of them, a pixel's width here).
            let x0 = qx * SIZE / 2 + 2;
            let y0 = qy * SIZE / 2 + 2;
            let first = albedo.get(x0 as usize, y0 as usize);
            for y in y0..y0 + SIZE / 2 - 4 {
                for x in x0..x0 + SIZE / 2 - 4 {
                    let a = albedo.get(x as usize, y as usize);
                    assert_close(how, a.to_array(), first.to_array(), 1e-6);
                }
            }
            seen.push(first);
        }
        for c in colours {
            assert!(
                seen.iter()
                    .any(|s| (0..3).all(|k| (s.to_array()[k] - c.to_array()[k]).abs() < 1e-5)),
                "{how}: texture colour {c:?} not among the quarters' albedos {seen:?}"
            );
        }
    }
}

#[test]
fn features_do_not_depend_on_threads_or_on_a_split_by_samples() {
    let shapes = vec![
        square(Vec3::Y * 2.0, -Vec3::Y, 0),
        square(Vec3::Y * 3.0, -Vec3::Y, 1),
    ];
    let pane = Material::ThinDielectric(Pane { eta: 1.5 });
    let scene = scene(shapes, vec![pane, diffuse(WALL)]);
    let with_threads = |threads: usize, first: u32, spp: u32| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| film_of(&scene, first, spp).features)
    };
    let whole = with_threads(2, 0, 24);
    assert_eq!(with_threads(1, 0, 24), whole);
    // Samples 0..5 and 5..24: the first piece takes 5 features a pixel, the second 11.
    let mut merged = with_threads(2, 0, 5);
    for (m, p) in merged.iter_mut().zip(with_threads(1, 5, 19)) {
        assert!(m.checked_merge(&p));
    }
    assert_eq!(merged, whole);
    assert!(whole.iter().all(|f| f.count == FEATURE_SAMPLES));
    // af_hf reads them off its own paths (whose draws at the pane are not the feature
    // samples' own), at no cost of rays.
    let sampled = sampled_features(&scene);
    let differ = whole.iter().zip(&sampled).filter(|(a, b)| a != b).count();
    // (Both draw stratified numbers: a pixel sees one or two reflections of its 16 either way.)
    assert!(
        differ > whole.len() / 8,
        "{differ} of {} pixels differ",
        whole.len()
    );
}
