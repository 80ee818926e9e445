//! Beyond the seed: a rectangle fitted to photons is only as exact as the photons, and with
//! exact portals direct light through an opening has almost no variance, so any excess area
//! shows. When the opening is cut in a planar occluder (the photons of a depth discontinuity
//! lie on it), each side of the rectangle is moved onto the occluder's edge by bisection with
//! rays along the portal's normal: inside the opening they pass, on the occluder they stop
//! in the portal's plane.

use fenestra_core::{Ray, Vec3};
use fenestra_render::portal::Portal;
use fenestra_scene::Scene;

/// Rays start this far (relative to the portal's size) from the plane.
const LIFT: f32 = 0.05;
/// A hit counts as the occluder when it lies this close to the plane (relative).
const ON_PLANE: f32 = 1e-3;
/// Bisection steps: the edge is found to 2^-24 of the search interval.
const STEPS: usize = 24;

/// Whether the point `q` of the portal's plane lies on the occluder.
fn blocked(scene: &Scene, q: Vec3, n: Vec3, size: f32) -> bool {
    let lift = LIFT * size;
    let ray = Ray::new(q + n * lift, -n);
    scene
        .intersect(&ray, 2.0 * lift)
        .is_some_and(|h| (h.t - lift).abs() < ON_PLANE * size)
}

/// The quad with each side moved onto the occluder's edge, or the quad unchanged when the
/// occluder is not where the photons say (the opening is not cut in a plane there).
pub fn snap_to_opening(scene: &Scene, portal: &Portal) -> Portal {
    let Portal::Quad { corner, e1, e2 } = portal else {
        return portal.clone();
    };
    let n = e1.cross(*e2).normalize_or_zero();
    let (l1, l2) = (e1.length(), e2.length());
    if n == Vec3::ZERO || l1 == 0.0 || l2 == 0.0 {
        return portal.clone();
    }
    let size = l1.max(l2);
    let c = *corner + (*e1 + *e2) * 0.5;
    let (u, v) = (*e1 / l1, *e2 / l2);
    // Half-extents along +u, -u, +v, -v.
    let mut half = [l1 * 0.5, l1 * 0.5, l2 * 0.5, l2 * 0.5];
    for (k, h) in half.iter_mut().enumerate() {
        let (dir, along, other) = match k {
            0 => (u, v, l2),
            1 => (-u, v, l2),
            2 => (v, u, l1),
            _ => (-v, u, l1),
        };
        // The side's edge is where probes at a quarter, half and three quarters of it turn
        // from passing to blocked; the outermost of the three keeps the opening covered.
        let mut edge: Option<f32> = Some(0.0);
        for f in [-0.25f32, 0.0, 0.25] {
            let base = c + along * (f * other);
            let at = |s: f32| blocked(scene, base + dir * s, n, size);
            let (mut open, mut shut) = (0.5 * *h, 1.02 * *h);
            if at(open) || !at(shut) {
                edge = None;
                break;
            }
            for _ in 0..STEPS {
                let mid = 0.5 * (open + shut);
                if at(mid) {
                    shut = mid;
                } else {
                    open = mid;
                }
            }
            edge = edge.map(|e| e.max(shut));
        }
        if let Some(e) = edge {
            *h = e;
        }
    }
    let centre = c + u * (0.5 * (half[0] - half[1])) + v * (0.5 * (half[2] - half[3]));
    let (a, b) = (
        u * (0.5 * (half[0] + half[1])),
        v * (0.5 * (half[2] + half[3])),
    );
    Portal::Quad {
        corner: centre - a - b,
        e1: a * 2.0,
        e2: b * 2.0,
    }
}
