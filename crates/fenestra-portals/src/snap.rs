//! Beyond the seed: a rectangle fitted to photons is only as exact as the photons, and with
//! exact portals direct light through an opening has almost no variance, so any excess area
//! shows. When the opening is cut in a planar occluder (the photons of a depth discontinuity
//! lie on it), each side of the rectangle is moved onto the occluder's edge by bisection with
//! rays along the portal's normal: inside the opening they pass, on the occluder they stop
//! in the portal's plane.

use crate::portal::Portal;
use fenestra_core::{Ray, Vec3};
use fenestra_scene::Scene;

/// Rays start this far (relative to the portal's size) from the plane.
const LIFT: f32 = 0.05;
/// A hit counts as the occluder when it lies this close to the plane (relative).
const ON_PLANE: f32 = 1e-3;
/// Bisection steps: the edge is found to 2^-24 of the search interval.
const STEPS: usize = 24;

/// The edge between `open` (where `is_open` holds) and `shut` (where it does not), to 2^-24
/// of their distance, on the shut side.
fn bisect(mut open: f32, mut shut: f32, is_open: impl Fn(f32) -> bool) -> f32 {
    for _ in 0..STEPS {
        let mid = 0.5 * (open + shut);
        if is_open(mid) {
            open = mid;
        } else {
            shut = mid;
        }
    }
    shut
}

/// Whether the point `q` of the portal's plane lies on the occluder.
fn blocked(scene: &Scene, q: Vec3, n: Vec3, size: f32) -> bool {
    let lift = LIFT * size;
    let ray = Ray::new(q + n * lift, -n);
    scene
        .intersect(&ray, 2.0 * lift)
        .is_some_and(|h| (h.t - lift).abs() < ON_PLANE * size)
}

/// One pass over the four sides of the rectangle (centre `c`, unit axes `u`, `v`, normal
/// `n`, half-extents along +u, -u, +v, -v): each side's edge where probes at a quarter, half
/// and three quarters of it turn from passing to blocked (the outermost of the three keeps
/// the opening covered), and the turn in the plane that aligns the rectangle with the
/// edges the probes found (mean over the sides). `None` when the occluder is not where the
/// photons say on some side.
fn snap_pass(
    scene: &Scene,
    c: Vec3,
    (u, v, n): (Vec3, Vec3, Vec3),
    mut half: [f32; 4],
) -> Option<([f32; 4], f32)> {
    let (width, height) = (half[0] + half[1], half[2] + half[3]);
    let size = width.max(height);
    let mut turn = 0.0;
    for (k, h) in half.iter_mut().enumerate() {
        // Outward direction, the direction along the side, its length, and how a tilt of
        // the edge towards `dir` turns the rectangle (counter-clockwise from u to v).
        let (dir, along, other, sign) = match k {
            0 => (u, v, height, -1.0),
            1 => (-u, v, height, 1.0),
            2 => (v, u, width, 1.0),
            _ => (-v, u, width, -1.0),
        };
        let mut edges = [0.0f32; 3];
        for (edge, f) in edges.iter_mut().zip([-0.25f32, 0.0, 0.25]) {
            let base = c + along * (f * other);
            let at = |s: f32| blocked(scene, base + dir * s, n, size);
            let (open, shut) = (0.5 * *h, 1.02 * *h);
            if at(open) || !at(shut) {
                return None;
            }
            *edge = bisect(open, shut, |s| !at(s));
        }
        *h = edges.iter().fold(0.0f32, |m, &e| m.max(e));
        turn += sign * ((edges[2] - edges[0]) / (0.5 * other)).atan() / 4.0;
    }
    Some((half, turn))
}

/// The quad with each side moved onto the occluder's edge, in the orientation of those
/// edges, or the quad unchanged when the occluder is not where the photons say (the opening
/// is not cut in a plane there).
pub fn snap_to_opening(scene: &Scene, portal: &Portal) -> Portal {
    let Portal::Quad { corner, e1, e2 } = portal else {
        return portal.clone();
    };
    let n = e1.cross(*e2).normalize_or_zero();
    let (l1, l2) = (e1.length(), e2.length());
    if n == Vec3::ZERO || l1 == 0.0 || l2 == 0.0 {
        return portal.clone();
    }
    let (mut u, mut v) = (*e1 / l1, *e2 / l2);
    let mut c = *corner + (*e1 + *e2) * 0.5;
    let mut half = [l1 * 0.5, l1 * 0.5, l2 * 0.5, l2 * 0.5];
    // First pass: edges and the orientation's error; second: the edges in the corrected
    // orientation.
    for pass in 0..2 {
        let Some((h, turn)) = snap_pass(scene, c, (u, v, n), half) else {
            if pass == 0 {
                return portal.clone();
            }
            break;
        };
        c += u * (0.5 * (h[0] - h[1])) + v * (0.5 * (h[2] - h[3]));
        let (a, b) = (0.5 * (h[0] + h[1]), 0.5 * (h[2] + h[3]));
        half = [a, a, b, b];
        if pass == 0 {
            let (sin, cos) = turn.sin_cos();
            u = u * cos + v * sin;
            v = n.cross(u);
        }
    }
    let (a, b) = (u * half[0], v * half[2]);
    Portal::Quad {
        corner: c - a - b,
        e1: a * 2.0,
        e2: b * 2.0,
    }
}

/// Where light can cross a plane of the scene: a point of the plane is closed when something
/// other than glass (the `passes` shapes, which let light through) lies within a tenth of the
/// portal's size of it along the normal: a wall, a frame, a blind's slat, a desk.
pub struct Opening<'a> {
    scene: &'a Scene,
    passes: &'a [bool],
}

/// Lines probed from each side of a rectangle inwards, and points probed along each line.
const LINES: usize = 64;
const LINE_POINTS: usize = 33;
/// Points of a grid side probed for [`Opening::open_fraction`].
const GRID: usize = 16;
/// A portal less open than this carries next to no light (a desk top, a wall) and is dropped.
pub const MIN_OPEN: f32 = 0.2;
/// The ring [`Opening::enclosed_fraction`] probes lies this far outside the portal
/// (relative to its size), at this many points.
const RING: f32 = 0.05;
const RING_POINTS: usize = 64;
/// A portal with less of its surroundings closed than this is no opening in an occluder.
pub const MIN_ENCLOSED: f32 = 0.5;
/// Glass layers a probe passes through at most.
const MAX_LAYERS: usize = 8;

impl<'a> Opening<'a> {
    /// The openings of `scene`, whose shapes `passes` marks let light through.
    pub fn new(scene: &'a Scene, passes: &'a [bool]) -> Self {
        Opening { scene, passes }
    }

    /// Whether light crosses the plane of normal `n` at `q` (portal size `size`).
    fn open(&self, q: Vec3, n: Vec3, size: f32) -> bool {
        let lift = 0.1 * size;
        let mut ray = Ray::new(q + n * lift, -n);
        let mut left = 2.0 * lift;
        for _ in 0..MAX_LAYERS {
            let Some(h) = self.scene.intersect(&ray, left) else {
                return true;
            };
            if !self.passes[h.shape as usize] {
                return false;
            }
            let si = self.scene.interaction(&ray, &h);
            left -= h.t;
            ray = Ray::new(si.spawn(ray.d), ray.d);
        }
        false
    }

    /// The fraction of points just outside the portal (a ring a twentieth of its size wide
    /// around it) where light does not cross its plane: an opening cut in a wall, a roof or
    /// a pane's frame has them all closed; a portal fitted to photons on a free-standing
    /// object (a lamp shade that stops a sunbeam) has open air around it.
    pub fn enclosed_fraction(&self, portal: &Portal) -> f32 {
        let (n, size) = (portal.normal(), portal.area().sqrt());
        let ring: Vec<Vec3> = match portal {
            Portal::Quad { corner, e1, e2 } => {
                let (g1, g2) = (RING * size / e1.length(), RING * size / e2.length());
                (0..RING_POINTS)
                    .map(|k| {
                        // Around the square [-g, 1 + g]^2, side by side.
                        let t = (k % (RING_POINTS / 4)) as f32 / (RING_POINTS / 4) as f32;
                        let (s, u) = match k / (RING_POINTS / 4) {
                            0 => (-g1 + t * (1.0 + 2.0 * g1), -g2),
                            1 => (1.0 + g1, -g2 + t * (1.0 + 2.0 * g2)),
                            2 => (1.0 + g1 - t * (1.0 + 2.0 * g1), 1.0 + g2),
                            _ => (-g1, 1.0 + g2 - t * (1.0 + 2.0 * g2)),
                        };
                        *corner + *e1 * s + *e2 * u
                    })
                    .collect()
            }
            Portal::Ellipse { center, a, b } => {
                let grow = 1.0 + RING * size / b.length().min(a.length());
                (0..RING_POINTS)
                    .map(|k| {
                        let t = k as f32 / RING_POINTS as f32 * std::f32::consts::TAU;
                        *center + (*a * t.cos() + *b * t.sin()) * grow
                    })
                    .collect()
            }
            Portal::Triangle { .. } => return 1.0,
        };
        let closed = ring.iter().filter(|&&q| !self.open(q, n, size)).count();
        closed as f32 / ring.len() as f32
    }

    /// The fraction of the portal's points (a grid over it) where light crosses its plane.
    pub fn open_fraction(&self, portal: &Portal) -> f32 {
        let (n, size) = (portal.normal(), portal.area().sqrt());
        let open = (0..GRID * GRID)
            .filter(|k| {
                let u = fenestra_core::Vec2::new(
                    ((k % GRID) as f32 + 0.5) / GRID as f32,
                    ((k / GRID) as f32 + 0.5) / GRID as f32,
                );
                self.open(portal.sample_area(u), n, size)
            })
            .count();
        open as f32 / (GRID * GRID) as f32
    }

    /// The quad with each side moved inwards to the first line along it where light crosses
    /// somewhere (the opening's bounding rectangle, whatever frames, mullions or slats lie
    /// inside it), or `None` when the quad holds no opening or too little of one
    /// ([`MIN_OPEN`]). Sides already on an open line stay.
    pub fn shrink(&self, portal: &Portal) -> Option<Portal> {
        let Portal::Quad { corner, e1, e2 } = portal else {
            return Some(portal.clone());
        };
        let n = e1.cross(*e2).normalize_or_zero();
        let (l1, l2) = (e1.length(), e2.length());
        if n == Vec3::ZERO || l1 == 0.0 || l2 == 0.0 {
            return None;
        }
        let (u, v) = (*e1 / l1, *e2 / l2);
        let c = *corner + (*e1 + *e2) * 0.5;
        let size = l1.max(l2);
        // Extents from c along +u, -u, +v, -v.
        let mut half = [l1 * 0.5, l1 * 0.5, l2 * 0.5, l2 * 0.5];
        for k in 0..4 {
            let (dir, along, lo, hi) = match k {
                0 => (u, v, -half[3], half[2]),
                1 => (-u, v, -half[3], half[2]),
                2 => (v, u, -half[1], half[0]),
                _ => (-v, u, -half[1], half[0]),
            };
            let line_open = |s: f32| {
                (0..LINE_POINTS).any(|i| {
                    let t = lo + (hi - lo) * (i as f32 + 0.5) / LINE_POINTS as f32;
                    self.open(c + dir * s + along * t, n, size)
                })
            };
            let h = half[k];
            let at = |j: usize| {
                h * (1.0 - j as f32 / LINES as f32) - half[k ^ 1] * (j as f32 / LINES as f32)
            };
            // From the side inwards across the whole rectangle to the opposite side.
            let first = (0..=LINES).find(|&j| line_open(at(j)))?;
            if first > 0 {
                half[k] = bisect(at(first), at(first - 1), line_open);
            }
        }
        if !(half[0] + half[1] > 0.0 && half[2] + half[3] > 0.0) {
            return None;
        }
        let centre = c + u * (0.5 * (half[0] - half[1])) + v * (0.5 * (half[2] - half[3]));
        let (a, b) = (
            u * (0.5 * (half[0] + half[1])),
            v * (0.5 * (half[2] + half[3])),
        );
        let shrunk = Portal::Quad {
            corner: centre - a - b,
            e1: a * 2.0,
            e2: b * 2.0,
        };
        (self.open_fraction(&shrunk) >= MIN_OPEN).then_some(shrunk)
    }
}
