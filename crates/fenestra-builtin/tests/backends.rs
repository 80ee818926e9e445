//! Embree and obvhs must agree on every ray: same shape, same primitive, same distance.
#![cfg(feature = "embree")]

use fenestra_core::{warp, Ray, Sampler, Vec3};
use fenestra_scene::{Backend, Shape, ShapeKind};

fn test_shapes() -> Vec<Shape> {
    let mut shapes = fenestra_builtin::load("box-4holes")
        .expect("builtin")
        .shapes;
    shapes.push(Shape::new(
        ShapeKind::Sphere {
            center: Vec3::new(0.1, 0.2, -0.2),
            radius: 0.15,
        },
        0,
    ));
    shapes.push(
        Shape::new(
            ShapeKind::Sphere {
                center: Vec3::new(-0.25, -0.1, 0.1),
                radius: 0.1,
            },
            0,
        )
        .flipped(),
    );
    let n = Vec3::new(0.3, -0.5, 0.8).normalize();
    shapes.push(Shape::new(
        ShapeKind::Disk {
            center: Vec3::new(0.2, -0.2, 0.2),
            normal: n,
            radius: 0.12,
        },
        0,
    ));
    shapes
}

#[test]
fn embree_and_obvhs_return_the_same_hits() {
    let shapes = test_shapes();
    let embree = Backend::Embree.build(&shapes).expect("embree");
    let obvhs = Backend::Obvhs.build(&shapes).expect("obvhs");
    let (mut hits, mut occluded) = (0, 0);
    for i in 0..20_000u32 {
        let mut s = Sampler::new(3, i as u64, 0);
        let o = Vec3::new(s.next_1d() - 0.5, s.next_1d() - 0.5, s.next_1d() - 0.5) * 1.3;
        let ray = Ray::new(o, warp::square_to_uniform_sphere(s.next_2d()));
        let tmax = if i % 3 == 0 { 0.3 } else { f32::INFINITY };
        let (a, b) = (embree.intersect(&ray, tmax), obvhs.intersect(&ray, tmax));
        // Origins within floating-point error of a surface are ambiguous for any tracer (the
        // renderer offsets its origins by far more than this); skip them.
        if a.or(b).is_some_and(|h| h.t < 1e-3) {
            continue;
        }
        match (a, b) {
            (Some(a), Some(b)) => {
                hits += 1;
                // Rays grazing a shared edge may pick either neighbour: accept equal distance.
                assert!(
                    (a.t - b.t).abs() <= 1e-4 * a.t.max(1.0),
                    "ray {i}: {a:?} vs {b:?}"
                );
                if a.shape != b.shape || a.prim != b.prim {
                    let same_point = (ray.at(a.t) - ray.at(b.t)).length() < 1e-4;
                    assert!(same_point, "ray {i}: {a:?} vs {b:?}");
                } else if a.shape < 3 {
                    assert!(
                        (a.u - b.u).abs() < 1e-3 && (a.v - b.v).abs() < 1e-3,
                        "ray {i}: {a:?} vs {b:?}"
                    );
                }
            }
            (None, None) => {}
            _ => panic!(
                "ray {i} from {o} along {}: embree {a:?}, obvhs {b:?}",
                ray.d
            ),
        }
        let oa = embree.occluded(&ray, tmax);
        assert_eq!(oa, obvhs.occluded(&ray, tmax), "ray {i}");
        assert_eq!(
            oa,
            a.is_some(),
            "ray {i}: occlusion agrees with closest hit"
        );
        occluded += oa as u32;
    }
    // The test means something only if both outcomes occur often.
    assert!(
        hits > 10_000 && occluded < 19_000,
        "hits {hits}, occluded {occluded}"
    );
}
