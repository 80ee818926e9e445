//! Every backend finds every hit, also where obvhs' own traversal would not: trees deeper
//! than its 32-entry stack, and geometry nearer a ray's origin than 1e-4 of the scene's size.

use fenestra_core::{warp, Ray, Sampler, Vec3};
use fenestra_scene::{Backend, Shape, ShapeKind, TriangleMesh};

fn directions(count: u64) -> impl Iterator<Item = Vec3> {
    (0..count).map(|i| {
        let mut s = Sampler::new(5, i, 0);
        warp::square_to_uniform_sphere(s.next_2d())
    })
}

/// A sphere of `2n x n` quads (split in triangles) around the origin.
fn shell(radius: f32, n: usize) -> TriangleMesh {
    let ring = 2 * n;
    let positions = (0..=n)
        .flat_map(|i| {
            let theta = std::f32::consts::PI * i as f32 / n as f32;
            (0..ring).map(move |j| {
                let phi = std::f32::consts::TAU * j as f32 / ring as f32;
                let (st, ct) = theta.sin_cos();
                Vec3::new(st * phi.cos(), st * phi.sin(), ct) * radius
            })
        })
        .collect();
    let indices = (0..n)
        .flat_map(|i| {
            (0..ring).flat_map(move |j| {
                let a = (i * ring + j) as u32;
                let b = (i * ring + (j + 1) % ring) as u32;
                let (c, d) = (a + ring as u32, b + ring as u32);
                [[a, b, d], [a, d, c]]
            })
        })
        .collect();
    TriangleMesh {
        positions,
        normals: None,
        uvs: None,
        indices,
    }
}

#[test]
fn nested_shells_are_hit_innermost_first() {
    // 600 shells make obvhs chain its tree 70 levels deep and keep up to 51 node groups
    // pending on rays from the centre (measured); the innermost is 5e7 times smaller than
    // the outermost.
    let shapes: Vec<Shape> = (0..600)
        .map(|i| Shape::new(ShapeKind::Mesh(shell(1.03f32.powi(i), 8)), 0))
        .collect();
    for backend in Backend::available() {
        let scene = backend.build(&shapes).expect("builds");
        for d in directions(2_000) {
            let ray = Ray::new(Vec3::ZERO, d);
            let hit = scene.intersect(&ray, f32::INFINITY);
            let hit = hit.unwrap_or_else(|| panic!("{}: no hit along {d}", backend.name()));
            assert_eq!(hit.shape, 0, "{} along {d}: {hit:?}", backend.name());
            assert!(scene.occluded(&ray, 1.0), "{} along {d}", backend.name());
            assert!(!scene.occluded(&ray, 0.9), "{} along {d}", backend.name());
        }
    }
}

#[test]
fn small_geometry_near_the_origin_of_a_ray_in_a_large_scene() {
    // A 1 mm sphere seen from 1 mm away, under a 20 km ground.
    let ground = TriangleMesh::quad(Vec3::new(0.0, -1.0, 0.0), Vec3::X * 1e4, Vec3::Z * 1e4);
    let shapes = vec![
        Shape::new(ShapeKind::Mesh(ground), 0),
        Shape::new(
            ShapeKind::Sphere {
                center: Vec3::ZERO,
                radius: 1e-3,
            },
            0,
        ),
    ];
    for backend in Backend::available() {
        let scene = backend.build(&shapes).expect("builds");
        for d in directions(500) {
            let ray = Ray::new(-2e-3 * d, d);
            let hit = scene.intersect(&ray, f32::INFINITY);
            let hit = hit.unwrap_or_else(|| panic!("{}: no hit along {d}", backend.name()));
            assert_eq!(hit.shape, 1, "{} along {d}: {hit:?}", backend.name());
            assert!(
                (hit.t - 1e-3).abs() < 1e-6,
                "{}: t {}",
                backend.name(),
                hit.t
            );
            assert!(scene.occluded(&ray, 1.1e-3), "{} along {d}", backend.name());
            assert!(
                !scene.occluded(&ray, 0.9e-3),
                "{} along {d}",
                backend.name()
            );
        }
    }
}

#[test]
fn copies_of_one_square_are_hit() {
    // Identical boxes chain obvhs' tree about one level per seven primitives.
    let square = TriangleMesh::quad(Vec3::ZERO, Vec3::X, Vec3::Y);
    let shapes: Vec<Shape> = (0..400)
        .map(|_| Shape::new(ShapeKind::Mesh(square.clone()), 0))
        .collect();
    for backend in Backend::available() {
        let scene = backend.build(&shapes).expect("builds");
        for d in directions(2_000).filter(|d| d.z < -0.5) {
            let ray = Ray::new(Vec3::new(0.2, -0.3, 1.0), d);
            let t = 1.0 / -d.z;
            let p = ray.at(t);
            let inside = p.x.abs() < 1.0 && p.y.abs() < 1.0;
            let hit = scene.intersect(&ray, f32::INFINITY);
            assert_eq!(hit.is_some(), inside, "{} along {d}", backend.name());
            if let Some(hit) = hit {
                assert!(
                    (hit.t - t).abs() < 1e-4 * t,
                    "{}: t {} not {t}",
                    backend.name(),
                    hit.t
                );
            }
            assert_eq!(
                scene.occluded(&ray, 2.0 * t),
                inside,
                "{} along {d}",
                backend.name()
            );
        }
    }
}

#[test]
fn directions_with_negative_zero_components_hit() {
    // -Vec3::Z is (-0, -0, -1): obvhs read -0 as a positive octant with a -inf slab and
    // missed every node, so a ray straight down missed the floor.
    let floor = TriangleMesh::quad(Vec3::ZERO, Vec3::X, Vec3::Y);
    let shapes = vec![Shape::new(ShapeKind::Mesh(floor), 0)];
    for backend in Backend::available() {
        let scene = backend.build(&shapes).expect("builds");
        for d in [
            -Vec3::Z,
            Vec3::new(-0.0, 0.0, -1.0),
            Vec3::new(0.0, -0.0, -1.0),
        ] {
            for o in [Vec3::new(-0.5, 0.0, 1.0), Vec3::new(0.3, 0.6, 2.0)] {
                let ray = Ray::new(o, d);
                // Embree rounds t to within an ulp or two depending on the CPU it runs on.
                let hit = scene.intersect(&ray, f32::INFINITY).map(|h| h.t);
                assert!(
                    hit.is_some_and(|t| (t - o.z).abs() <= 4.0 * f32::EPSILON * o.z),
                    "{} from {o} along {d:?}: {hit:?}",
                    backend.name()
                );
                assert!(scene.occluded(&ray, 10.0), "{} occluded", backend.name());
            }
        }
    }
}

#[test]
fn packets_find_the_hits_of_single_rays() {
    // Meshes, a sphere and a disk (user geometry in Embree, whose callbacks then see 8-wide
    // packets); rays from random points in all directions, with finite and infinite tmax.
    let shapes = vec![
        Shape::new(ShapeKind::Mesh(shell(1.0, 6)), 0),
        Shape::new(ShapeKind::Mesh(shell(0.3, 4)), 0),
        Shape::new(
            ShapeKind::Sphere {
                center: Vec3::new(0.4, 0.1, -0.2),
                radius: 0.2,
            },
            0,
        ),
        Shape::new(
            ShapeKind::Disk {
                center: Vec3::new(-0.4, 0.0, 0.3),
                normal: Vec3::Z,
                radius: 0.25,
            },
            0,
        ),
    ];
    for backend in Backend::available() {
        let scene = backend.build(&shapes).expect("builds");
        let mut kinds = [0usize; 5];
        for packet in 0..500u64 {
            let rays: [Ray; fenestra_scene::PACKET] = std::array::from_fn(|i| {
                let mut s = Sampler::new(9, packet * 8 + i as u64, 0);
                let o = Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) * 1.2 - 0.6;
                Ray::new(o, warp::square_to_uniform_sphere(s.next_2d()))
            });
            let tmax = std::array::from_fn(|i| if i % 2 == 0 { f32::INFINITY } else { 0.3 });
            let hits = scene.intersect8(&rays, tmax);
            let blocked = scene.occluded8(&rays, tmax);
            for i in 0..fenestra_scene::PACKET {
                let one = scene.intersect(&rays[i], tmax[i]);
                let name = backend.name();
                assert_eq!(
                    hits[i].map(|h| (h.shape, h.prim)),
                    one.map(|h| (h.shape, h.prim)),
                    "{name}: ray {i} of packet {packet}"
                );
                if let (Some(a), Some(b)) = (hits[i], one) {
                    assert!(
                        (a.t - b.t).abs() <= 1e-5 * b.t,
                        "{name}: t {} against {}",
                        a.t,
                        b.t
                    );
                }
                assert_eq!(
                    blocked[i],
                    scene.occluded(&rays[i], tmax[i]),
                    "{name}: ray {i} of packet {packet}"
                );
                kinds[one.map_or(4, |h| h.shape as usize)] += 1;
            }
        }
        // Every shape was hit by some ray, and some rays hit nothing within tmax.
        assert!(
            kinds.iter().all(|&k| k > 0),
            "{}: {kinds:?}",
            backend.name()
        );
    }
}
