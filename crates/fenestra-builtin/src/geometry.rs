//! Building blocks of the procedural scenes: boxes, walls with openings, parametric grids, a
//! procedural sky, and a small scene assembler.

use fenestra_core::image::Image;
use fenestra_core::{Rgb, Vec3, PI};
use fenestra_scene::environment::latlong_direction;
use fenestra_scene::light::{Emission, EnvironmentDesc, LightDesc};
use fenestra_scene::mesh::grid;
use fenestra_scene::{Camera, Material, RenderDefaults, SceneDesc, Shape, ShapeKind, TriangleMesh};
use std::sync::Arc;

/// A rectangle (min corner, max corner) in a wall's own (u, v) coordinates.
pub type Rect = ([f32; 2], [f32; 2]);

/// Collects shapes and materials of a procedural scene.
#[derive(Default)]
pub struct Assembler {
    pub shapes: Vec<Shape>,
    pub materials: Vec<Material>,
    pub lights: Vec<LightDesc>,
}

impl Assembler {
    pub fn material(&mut self, m: Material) -> usize {
        self.materials.push(m);
        self.materials.len() - 1
    }

    pub fn mesh(&mut self, mesh: TriangleMesh, material: usize) {
        if !mesh.indices.is_empty() {
            self.shapes
                .push(Shape::new(ShapeKind::Mesh(mesh), material));
        }
    }

    /// A one-sided emitter radiating `radiance` along its normal.
    pub fn emitter(&mut self, kind: ShapeKind, material: usize, radiance: Rgb) {
        self.shapes
            .push(Shape::new(kind, material).emitting(Emission::radiance(radiance)));
    }

    pub fn finish(self, name: &str, camera: Camera, defaults: RenderDefaults) -> SceneDesc {
        SceneDesc {
            name: name.into(),
            shapes: self.shapes,
            materials: self.materials,
            lights: self.lights,
            camera,
            defaults,
            portals: Vec::new(),
        }
    }
}

/// A camera from fixed, valid parameters (the built-in scenes' own).
pub fn camera(eye: Vec3, target: Vec3, fov_y: f32) -> Camera {
    Camera::look_at(eye, target, Vec3::Z, fov_y).unwrap_or_else(|e| unreachable!("{e}"))
}

/// An axis-aligned box with outward-facing triangles.
pub fn cuboid(lo: Vec3, hi: Vec3) -> TriangleMesh {
    let c = (lo + hi) * 0.5;
    let h = (hi - lo) * 0.5;
    let (x, y, z) = (Vec3::X * h.x, Vec3::Y * h.y, Vec3::Z * h.z);
    let mut m = TriangleMesh::default();
    for (centre, u, v) in [
        (c + x, y, z),
        (c - x, z, y),
        (c + y, z, x),
        (c - y, x, z),
        (c + z, x, y),
        (c - z, y, x),
    ] {
        m.append(&TriangleMesh::quad(centre, u, v));
    }
    m
}

/// Rectangles with their two coordinates exchanged (for walls spanned the other way round).
pub fn transposed(rects: &[Rect]) -> Vec<Rect> {
    rects
        .iter()
        .map(|(lo, hi)| ([lo[1], lo[0]], [hi[1], hi[0]]))
        .collect()
}

/// A planar rectangle minus rectangular openings: the cells of the grid through all opening
/// edges that lie outside every opening. The plane spans `origin + s u + t v` for (s, t) in
/// `extent` = ([s0, t0], [s1, t1]); its normal is u x v.
pub fn wall_with_openings(
    origin: Vec3,
    u: Vec3,
    v: Vec3,
    extent: Rect,
    openings: &[Rect],
) -> TriangleMesh {
    let mut ss = vec![extent.0[0], extent.1[0]];
    let mut ts = vec![extent.0[1], extent.1[1]];
    for (lo, hi) in openings {
        ss.extend([lo[0], hi[0]]);
        ts.extend([lo[1], hi[1]]);
    }
    for w in [&mut ss, &mut ts] {
        w.sort_by(f32::total_cmp);
        w.dedup();
    }
    let inside = |x: f32, lo: f32, hi: f32| x > lo && x < hi;
    let mut mesh = TriangleMesh::default();
    for i in 0..ss.len() - 1 {
        for j in 0..ts.len() - 1 {
            let c = [(ss[i] + ss[i + 1]) * 0.5, (ts[j] + ts[j + 1]) * 0.5];
            let in_extent =
                inside(c[0], extent.0[0], extent.1[0]) && inside(c[1], extent.0[1], extent.1[1]);
            let in_opening = openings
                .iter()
                .any(|(lo, hi)| inside(c[0], lo[0], hi[0]) && inside(c[1], lo[1], hi[1]));
            if in_extent && !in_opening {
                let hu = u * ((ss[i + 1] - ss[i]) * 0.5);
                let hv = v * ((ts[j + 1] - ts[j]) * 0.5);
                mesh.append(&TriangleMesh::quad(origin + u * c[0] + v * c[1], hu, hv));
            }
        }
    }
    mesh
}

/// A room [0, w] x [0, d] x [0, h] whose wall at y = 0 (facing +y) has the openings
/// `windows`, (x, z) rectangles: the floor, and the shell (ceiling, the walls at x = 0,
/// x = w and y = d, the window wall).
pub fn room(w: f32, d: f32, h: f32, windows: &[Rect]) -> (TriangleMesh, TriangleMesh) {
    let floor = TriangleMesh::quad(
        Vec3::new(w / 2.0, d / 2.0, 0.0),
        Vec3::X * (w / 2.0),
        Vec3::Y * (d / 2.0),
    );
    let mut shell = TriangleMesh::quad(
        Vec3::new(w / 2.0, d / 2.0, h),
        Vec3::Y * (d / 2.0),
        Vec3::X * (w / 2.0),
    );
    for (centre, u, v) in [
        (
            Vec3::new(0.0, d / 2.0, h / 2.0),
            Vec3::Y * (d / 2.0),
            Vec3::Z * (h / 2.0),
        ),
        (
            Vec3::new(w, d / 2.0, h / 2.0),
            Vec3::Z * (h / 2.0),
            Vec3::Y * (d / 2.0),
        ),
        (
            Vec3::new(w / 2.0, d, h / 2.0),
            Vec3::X * (w / 2.0),
            Vec3::Z * (h / 2.0),
        ),
    ] {
        shell.append(&TriangleMesh::quad(centre, u, v));
    }
    shell.append(&wall_with_openings(
        Vec3::ZERO,
        Vec3::Z,
        Vec3::X,
        ([0.0, 0.0], [h, w]),
        // (z, x) coordinates: normal z x x = +y.
        &transposed(windows),
    ));
    (floor, shell)
}

/// A vertical cylinder (open ends) of `radius` from `base` up `height`, with `flutes` grooves
/// of relative depth `depth` (0 for a plain column).
pub fn column(
    base: Vec3,
    radius: f32,
    height: f32,
    segments: usize,
    rings: usize,
    flutes: f32,
    depth: f32,
) -> TriangleMesh {
    grid(segments, rings, true, |s, t| {
        let phi = 2.0 * PI * s;
        let r = radius * (1.0 - depth * (0.5 - 0.5 * (flutes * phi).cos()));
        base + Vec3::new(r * phi.cos(), r * phi.sin(), height * t)
    })
}

/// A latitude-longitude procedural sky (row 0 at the zenith): a blue gradient brightening
/// towards the horizon, a soft bright region around `sun` (unit), dark ground below.
pub fn sky(width: usize, height: usize, sun: Vec3, strength: f32) -> EnvironmentDesc {
    let mut img = Image::new(width, height);
    for row in 0..height {
        for col in 0..width {
            let d = latlong_direction(col, row, width, height);
            let c = if d.z < 0.0 {
                Rgb::new(0.12, 0.11, 0.10)
            } else {
                let zenith = Rgb::new(0.25, 0.45, 1.0);
                let horizon = Rgb::new(1.0, 0.95, 0.9);
                let k = (1.0 - d.z).powi(3);
                let glow = (d.dot(sun).max(0.0)).powi(64) * 40.0;
                zenith * (1.0 - k) + horizon * k + Rgb::new(1.0, 0.9, 0.75) * glow
            };
            img.set(col, row, c * strength);
        }
    }
    EnvironmentDesc::Image {
        image: Arc::new(img),
        scale: Rgb::ONE,
        to_world: glam::Mat3::IDENTITY,
    }
}

/// A square checkerboard image of `n` x `n` squares, `texels` per square.
pub fn checker(n: usize, texels: usize, a: Rgb, b: Rgb) -> Image {
    let size = n * texels;
    let mut img = Image::new(size, size);
    for y in 0..size {
        for x in 0..size {
            img.set(
                x,
                y,
                if (x / texels + y / texels).is_multiple_of(2) {
                    a
                } else {
                    b
                },
            );
        }
    }
    img
}

/// A number in [0, 1) from two integers (procedural placement, test points).
pub fn unit(a: u32, b: u32) -> f32 {
    use fenestra_core::sampler::{hash_combine, hash_u32};
    hash_u32(hash_combine(a, b)) as f32 / (u32::MAX as f32 + 1.0)
}

/// How many of `lights` (points) each of `points` sees unoccluded in `scene`, on average.
#[cfg(test)]
pub fn lights_visible(scene: &fenestra_scene::Scene, points: &[Vec3], lights: &[Vec3]) -> f64 {
    let mut visible = 0usize;
    for &p in points {
        for &l in lights {
            let d = l - p;
            let dist = d.length();
            let ray = fenestra_core::Ray::new(p, d / dist);
            visible += usize::from(!scene.occluded(&ray, dist * 0.999));
        }
    }
    visible as f64 / points.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(m: &TriangleMesh) -> f32 {
        (0..m.indices.len()).map(|i| m.triangle_area(i)).sum()
    }

    #[test]
    fn cuboid_faces_outwards_and_walls_lose_their_openings() {
        let b = cuboid(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
        assert!((area(&b) - 2.0 * (2.0 + 3.0 + 6.0)).abs() < 1e-5);
        let centre = Vec3::new(0.5, 1.0, 1.5);
        for t in 0..b.indices.len() {
            let [p, q, r] = b.triangle(t);
            let n = (q - p).cross(r - p);
            assert!(
                n.dot((p + q + r) / 3.0 - centre) > 0.0,
                "triangle {t} faces inwards"
            );
        }
        let w = wall_with_openings(
            Vec3::ZERO,
            Vec3::X,
            Vec3::Z,
            ([0.0, 0.0], [4.0, 3.0]),
            &[([1.0, 1.0], [2.0, 2.0]), ([3.0, 0.5], [3.5, 2.5])],
        );
        assert!((area(&w) - (12.0 - 1.0 - 1.0)).abs() < 1e-5);
        let [p, q, r] = w.triangle(0);
        assert!((q - p).cross(r - p).y < 0.0, "normal is u x v = x x z = -y");
    }
}
