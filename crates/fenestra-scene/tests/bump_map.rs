//! Bump maps tilt the shading normal as the displaced surface's normal dp'/du x dp'/dv:
//! exactly so for a height that is linear in u or v on a flat quad (bilinear lookups
//! reproduce a linear ramp, so the forward difference is its slope); a constant height on a
//! sphere leaves its normal radial; a sphere's uv is pbrt-v4's (v = 1 at the +z pole).

use fenestra_core::image::Image;
use fenestra_core::{Ray, Rgb, Vec3};
use fenestra_scene::material::{BumpMap, Relief};
use fenestra_scene::{
    Backend, Camera, ImageTexture, Material, RenderDefaults, Scene, SceneDesc, Shape, ShapeKind,
    SurfaceInteraction, TriangleMesh,
};
use std::sync::Arc;

/// A height texture of `w` x `h` texels with values `f(x, y)` (x right, y down the image).
fn heights(w: usize, h: usize, f: impl Fn(usize, usize) -> f32) -> Arc<Relief> {
    let mut img = Image::new(w, h);
    for y in 0..h {
        for x in 0..w {
            img.set(x, y, Rgb::splat(f(x, y)));
        }
    }
    Arc::new(Relief::Bump(BumpMap {
        displacement: Arc::new(ImageTexture::new(Arc::new(img), "h.exr".into())),
    }))
}

fn scene(kind: ShapeKind, relief: Option<Arc<Relief>>) -> Scene {
    let mut shape = Shape::new(kind, 0);
    shape.relief = relief;
    scene_of(shape)
}

fn scene_of(shape: Shape) -> Scene {
    let desc = SceneDesc {
        name: "bumped".into(),
        shapes: vec![shape],
        materials: vec![Material::diffuse(0.5)],
        lights: vec![],
        camera: Camera::look_at(Vec3::Z * 3.0, Vec3::ZERO, Vec3::Y, 60.0).expect("camera"),
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    };
    Scene::build(desc, Backend::Obvhs).expect("scene")
}

fn hit(scene: &Scene, from: Vec3, to: Vec3) -> SurfaceInteraction {
    let ray = Ray::new(from, (to - from).normalize());
    let h = scene.intersect(&ray, f32::INFINITY).expect("hit");
    scene.interaction(&ray, &h)
}

/// The quad spans 2 units along x (u) and y (v): dp/du = (2, 0, 0), dp/dv = (0, 2, 0).
fn plate(relief: Arc<Relief>) -> SurfaceInteraction {
    let quad = TriangleMesh::quad(Vec3::ZERO, Vec3::X, Vec3::Y);
    let s = scene(ShapeKind::Mesh(quad), Some(relief));
    hit(&s, Vec3::new(0.3, -0.2, 2.0), Vec3::new(0.3, -0.2, 0.0))
}

#[test]
fn a_height_ramp_tilts_a_plane_as_the_displaced_surface_does() {
    let (n, slope) = (64usize, 0.5f32);
    // d = slope u: (2, 0, slope) x (0, 2, 0) = (-2 slope, 0, 4).
    let along_u = plate(heights(n, 1, |x, _| slope * (x as f32 + 0.5) / n as f32));
    let expect = Vec3::new(-2.0 * slope, 0.0, 4.0).normalize();
    assert!(
        (along_u.ns - expect).length() < 1e-4,
        "{} vs {expect}",
        along_u.ns
    );
    assert_eq!(along_u.ng, Vec3::Z);
    // d = slope v (image rows run down, v up): (2, 0, 0) x (0, 2, slope) = (0, -2 slope, 4).
    let along_v = plate(heights(1, n, |_, y| {
        slope * (1.0 - (y as f32 + 0.5) / n as f32)
    }));
    let expect = Vec3::new(0.0, -2.0 * slope, 4.0).normalize();
    assert!(
        (along_v.ns - expect).length() < 1e-4,
        "{} vs {expect}",
        along_v.ns
    );
    // A flat height tilts nothing.
    let flat = plate(heights(4, 4, |_, _| 0.3));
    assert!((flat.ns - Vec3::Z).length() < 1e-6, "{}", flat.ns);
}

#[test]
fn a_sphere_keeps_its_normal_under_a_constant_height_and_pbrt_v4_uvs() {
    let ball = ShapeKind::Sphere {
        center: Vec3::ZERO,
        radius: 1.0,
    };
    let s = scene(ball.clone(), Some(heights(2, 2, |_, _| 0.3)));
    for to in [Vec3::new(0.2, 0.1, 0.0), Vec3::new(-0.3, 0.4, 0.0)] {
        let si = hit(&s, Vec3::new(0.0, 0.0, 3.0) + to, to);
        let radial = si.p.normalize();
        assert!((si.ns - radial).length() < 1e-4, "{} vs {radial}", si.ns);
    }
    let plain = scene(ball, None);
    let top = hit(&plain, Vec3::new(0.01, 0.0, 3.0), Vec3::new(0.01, 0.0, 0.0));
    assert!(top.uv.y > 0.99, "v at the +z pole: {}", top.uv.y);
}

/// pbrt-v4 parametrises a sphere in its object space: a turned sphere's uv, and so its bump,
/// turn with it (they stayed in the world's axes before, which put textures and bumps on
/// turned spheres elsewhere: regions of a bumped sphere 15% off pbrt-v4's render).
#[test]
fn a_turned_spheres_uv_and_bump_turn_with_it() {
    let ball = Shape::new(
        ShapeKind::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        },
        0,
    );
    // 90 degrees about y (as pbrt-v4's Rotate 90 0 1 0): the object's +z pole to world +x.
    let turn = glam::DMat4::from_rotation_y(std::f64::consts::FRAC_PI_2);
    let turned = fenestra_scene::transform::transformed(&ball, &turn).expect("turns");
    let relief = heights(16, 8, |x, y| {
        0.02 * x as f32 + 0.05 * (y as f32 * 0.7).sin()
    });
    let lone = |shape: &Shape| {
        let mut shape = shape.clone();
        shape.relief = Some(relief.clone());
        scene_of(shape)
    };
    let (plain, turned_scene) = (lone(&ball), lone(&turned));
    let at_pole = hit(
        &turned_scene,
        Vec3::new(3.0, 0.01, 0.0),
        Vec3::new(0.0, 0.01, 0.0),
    );
    assert!(
        at_pole.uv.y > 0.99,
        "v at the turned +z pole: {}",
        at_pole.uv.y
    );
    let r = turn.as_mat4();
    for p in [
        Vec3::new(0.3, -0.5, 0.6),
        Vec3::new(-0.7, 0.2, 0.1),
        Vec3::new(0.1, 0.8, -0.4),
    ] {
        let p = p.normalize();
        let a = hit(&plain, p * 3.0, p);
        let q = r.transform_vector3(p);
        let b = hit(&turned_scene, q * 3.0, q);
        assert!((a.uv - b.uv).length() < 1e-4, "{} vs {}", a.uv, b.uv);
        let expected = r.transform_vector3(a.ns);
        assert!((b.ns - expected).length() < 1e-4, "{} vs {expected}", b.ns);
        assert!(
            (a.ns - a.ng).length() > 1e-3,
            "the bump tilts the normal at {p}"
        );
    }
}
