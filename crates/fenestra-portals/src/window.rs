//! Openings found as a whole (beyond seed 000). The seed clusters photons first (Alg. 2) and
//! fits a plane to each cluster (Alg. 3); on a real window the photons break up wherever frames,
//! mullions, blinds or panes do, and on a large window wall they are too sparse for DBSCAN's
//! eps: Bitterli's classroom gave dozens of slivers on its window frames, the dining room 27 on
//! its blinds' slats. Here the plane comes first: RANSAC over all photons finds the plane that
//! holds most of them (a wall with its windows; a blind's slats lie within a few centimetres of
//! one plane), a coarser clustering in that plane separates its windows, and each window gets
//! the rectangle around its photons, oriented to the wall, shrunk onto the opening; then the
//! plane's photons are set aside and the next plane is sought.

use crate::cluster::{dbscan, DbscanParams};
use crate::fitted::{quad_portal, Estimated};
use crate::portal::Portal;
use crate::ransac::{ransac_plane, Plane, Ransac};
use crate::rectangle::{min_area_rectangle, Rectangle};
use crate::snap::Opening;
use fenestra_core::Vec3;
use glam::{DVec2, DVec3};

/// Planes sought at most.
const MAX_PLANES: usize = 16;
/// A plane holding fewer photons than this fraction of all of them ends the search.
const MIN_PLANE_SHARE: f64 = 0.02;
/// Photons deposited by depth around one window lie within this distance of each other in
/// their plane (m): frames and mullions are thinner, the wall between two windows usually
/// wider. Photons deposited on glass lie on the panes themselves, and a gap between them is a
/// frame or a wall: they are separated at DBSCAN's eps.
pub const WINDOW_GAP: f32 = 0.3;
/// A window needs this many photons.
const MIN_WINDOW_PHOTONS: usize = 16;
/// An axis-aligned rectangle is preferred to the minimum-area one when at most this much larger
/// (architecture is built along the axes; noisy photons tilt the minimum-area rectangle).
const AXIS_PREFERENCE: f64 = 1.05;

/// The windows among `points`, photons of one window lying within `gap` of each other: each
/// portal with the indices of its photons.
pub fn windows(
    opening: &Opening,
    points: &[Vec3],
    ransac: &Ransac,
    gap: f32,
) -> Vec<(Vec<usize>, Estimated)> {
    let all: Vec<DVec3> = points.iter().map(|p| p.as_dvec3()).collect();
    let mut left: Vec<usize> = (0..points.len()).collect();
    let min_plane = ((MIN_PLANE_SHARE * points.len() as f64) as usize).max(MIN_WINDOW_PHOTONS);
    let search = Ransac {
        tau: 1.0, // the plane holding most photons, not the first good one
        ..*ransac
    };
    let mut found = Vec::new();
    for _ in 0..MAX_PLANES {
        if left.len() < min_plane {
            break;
        }
        let pts: Vec<DVec3> = left.iter().map(|&i| all[i]).collect();
        let Some(fit) = ransac_plane(&pts, &search) else {
            break;
        };
        if fit.inliers.len() < min_plane {
            break;
        }
        let on_plane: Vec<usize> = fit.inliers.iter().map(|&k| left[k]).collect();
        found.extend(plane_windows(opening, &fit.plane, &on_plane, points, gap));
        let mut taken = vec![false; left.len()];
        for &k in &fit.inliers {
            taken[k] = true;
        }
        left = left
            .iter()
            .zip(&taken)
            .filter(|(_, &t)| !t)
            .map(|(&i, _)| i)
            .collect();
    }
    found
}

/// The windows of one plane: its photons (`on_plane`, indices into `points`) clustered with
/// `gap`, a rectangle around each cluster shrunk onto its opening.
fn plane_windows(
    opening: &Opening,
    plane: &Plane,
    on_plane: &[usize],
    points: &[Vec3],
    gap: f32,
) -> Vec<(Vec<usize>, Estimated)> {
    let flat: Vec<Vec3> = on_plane
        .iter()
        .map(|&i| {
            let q = plane.to_plane(points[i].as_dvec3());
            Vec3::new(q.x as f32, q.y as f32, 0.0)
        })
        .collect();
    let groups = dbscan(
        &flat,
        DbscanParams {
            eps: gap,
            min_points: 4,
        },
    );
    groups
        .into_iter()
        .filter(|g| g.len() >= MIN_WINDOW_PHOTONS)
        .filter_map(|g| {
            let pts: Vec<DVec2> = g
                .iter()
                .map(|&k| DVec2::new(flat[k].x as f64, flat[k].y as f64))
                .collect();
            let rect = wall_rectangle(plane, &pts)?;
            let portal = opening.shrink(&quad_portal(plane, rect))?;
            let photons: Vec<usize> = g.iter().map(|&k| on_plane[k]).collect();
            let estimated = Estimated {
                portal,
                cluster: 0,
                photons: photons.len(),
                inliers: photons.len(),
                mvce_iterations: 0,
            };
            Some((photons, estimated))
        })
        .collect()
}

/// The rectangle around `p` (in-plane coordinates of `plane`) with its sides along the
/// projections of the world axes into the plane when that costs at most [`AXIS_PREFERENCE`]
/// in area, else the minimum-area one.
fn wall_rectangle(plane: &Plane, p: &[DVec2]) -> Option<Rectangle> {
    let smallest = min_area_rectangle(p)?;
    let (u, v) = plane.basis();
    let aligned = [DVec3::X, DVec3::Y, DVec3::Z]
        .into_iter()
        .filter_map(|axis| {
            let along = DVec2::new(axis.dot(u), axis.dot(v)).try_normalize()?;
            Some(bounding_rectangle(p, along))
        })
        .min_by(|a, b| a.area().total_cmp(&b.area()))?;
    Some(if aligned.area() <= AXIS_PREFERENCE * smallest.area() {
        aligned
    } else {
        smallest
    })
}

/// The bounding rectangle of `p` with sides along the unit `u` and its perpendicular.
fn bounding_rectangle(p: &[DVec2], u: DVec2) -> Rectangle {
    let v = u.perp();
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for q in p {
        let c = DVec2::new(q.dot(u), q.dot(v));
        lo = lo.min(c);
        hi = hi.max(c);
    }
    let (mid, size) = ((lo + hi) * 0.5, hi - lo);
    Rectangle {
        center: u * mid.x + v * mid.y,
        half: [u * (size.x * 0.5), v * (size.y * 0.5)],
    }
}

/// Whether the portal `inner` lies within the portal `outer`: in its plane and inside its
/// outline, grown by `tolerance` of its size.
pub fn within(inner: &Portal, outer: &Portal, tolerance: f32) -> bool {
    let Portal::Quad { corner, e1, e2 } = outer else {
        return false;
    };
    let size = outer.area().sqrt();
    let d = inner.center() - *corner;
    let off_plane = d.dot(outer.normal()).abs();
    let (s, t) = (
        d.dot(*e1) / e1.length_squared(),
        d.dot(*e2) / e2.length_squared(),
    );
    let grow = tolerance * size;
    let (gs, gt) = (grow / e1.length(), grow / e2.length());
    off_plane <= grow && (-gs..=1.0 + gs).contains(&s) && (-gt..=1.0 + gt).contains(&t)
}
