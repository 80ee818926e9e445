//! Rectangles covering planar points: the PCA rectangle of seed 000 §5.1 and, beyond the
//! seed, the minimum-area enclosing rectangle (one of its sides lies along an edge of the
//! points' convex hull, Freeman and Shapira 1975), which fits square openings far tighter
//! than the covering ellipse (a square's is pi/2 times its area).

use crate::linalg::{outer, sym_eigen};
use glam::{DMat3, DVec2};

/// A rectangle as centre and two perpendicular half-edge vectors.
#[derive(Clone, Copy, Debug)]
pub struct Rectangle {
    /// Centre.
    pub center: DVec2,
    /// Half-edge vectors, perpendicular.
    pub half: [DVec2; 2],
}

impl Rectangle {
    /// Area.
    pub fn area(&self) -> f64 {
        4.0 * self.half[0].length() * self.half[1].length()
    }

    /// Whether `x` lies inside, with a relative tolerance on each axis.
    pub fn contains(&self, x: DVec2, tol: f64) -> bool {
        let d = x - self.center;
        self.half
            .iter()
            .all(|h| (d.dot(*h) / h.length_squared()).abs() <= 1.0 + tol)
    }
}

/// The PCA rectangle of §5.1: oriented along the principal axes of the in-plane points,
/// centred on their mean, reaching the farthest point along each axis. Returns the centre
/// and the two half-edge vectors.
pub fn pca_rectangle(p: &[DVec2]) -> Option<Rectangle> {
    if p.len() < 3 {
        return None;
    }
    let mean = p.iter().fold(DVec2::ZERO, |a, x| a + *x) / p.len() as f64;
    let cov = p.iter().fold(DMat3::ZERO, |a, x| {
        let d = (*x - mean).extend(0.0);
        a + outer(d, d)
    });
    let (_, vecs) = sym_eigen(&cov);
    let axes: Vec<DVec2> = vecs
        .iter()
        .filter(|v| v.z.abs() < 0.5)
        .map(|v| v.truncate().normalize())
        .collect();
    if axes.len() != 2 {
        return None;
    }
    let half = |a: DVec2| {
        p.iter()
            .map(|x| (*x - mean).dot(a).abs())
            .fold(0.0f64, f64::max)
    };
    Some(Rectangle {
        center: mean,
        half: [axes[0] * half(axes[0]), axes[1] * half(axes[1])],
    })
}

/// Convex hull of `p` counter-clockwise (Andrew's monotone chain), without collinear points.
pub fn convex_hull(p: &[DVec2]) -> Vec<DVec2> {
    let mut pts: Vec<DVec2> = p.to_vec();
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::with_capacity(2 * pts.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &DVec2>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for &q in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

/// The smallest-area rectangle containing `p`: for each hull edge, the bounding box of the
/// hull in the frame of that edge. `None` for fewer than 3 points or all on one line.
pub fn min_area_rectangle(p: &[DVec2]) -> Option<Rectangle> {
    let hull = convex_hull(p);
    if hull.len() < 3 {
        return None;
    }
    let mut best: Option<(f64, Rectangle)> = None;
    for i in 0..hull.len() {
        let e = hull[(i + 1) % hull.len()] - hull[i];
        let Some(u) = e.try_normalize() else { continue };
        let v = u.perp();
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for q in &hull {
            let c = DVec2::new(q.dot(u), q.dot(v));
            lo = lo.min(c);
            hi = hi.max(c);
        }
        let size = hi - lo;
        let area = size.x * size.y;
        if best.as_ref().is_none_or(|(a, _)| area < *a) {
            let mid = (lo + hi) * 0.5;
            best = Some((
                area,
                Rectangle {
                    center: u * mid.x + v * mid.y,
                    half: [u * (size.x * 0.5), v * (size.y * 0.5)],
                },
            ));
        }
    }
    best.filter(|(a, _)| *a > 0.0).map(|(_, r)| r)
}

/// The opening inside a ring of points around it: photons deposited by depth lie on the
/// occluder around an opening, so the opening's edges are the ring's inner edges, not its
/// outer ones. In a frame turned by up to 3 degrees from `r`'s (searched to 0.01 degree) (the enclosing rectangle
/// follows the ring's noisy outer edge), each side moves inwards to a low quantile of the
/// distances of the points in the middle half of that side (corners are left out: there the
/// sides' strips meet); the one holding fewest points wins, the largest among equals. `None`
/// when there is none, i.e. the opening is not rectangular (a round one leaves points in the
/// corners).
pub fn inner_rectangle(r: &Rectangle, p: &[DVec2]) -> Option<Rectangle> {
    // Orientations within 3 degrees in 0.1-degree steps, then within 0.1 degree of the best
    // in 0.01-degree steps.
    let axis = r.half[0].normalize();
    let mut best: Option<(f64, Rectangle, usize)> = None;
    for (centre, step, steps) in [(0.0, 0.1, 30), (f64::NAN, 0.01, 10)] {
        let centre = if centre.is_nan() {
            best.map_or(0.0, |(a, ..)| a)
        } else {
            centre
        };
        for k in -steps..=steps {
            let angle = centre + k as f64 * step;
            let u = DVec2::from_angle(angle.to_radians()).rotate(axis);
            // Fewest points inside first (a turned rectangle cuts into the ring at its
            // corners), then the largest.
            if let Some((c, inside)) = inner_in_frame(r.center, u, p) {
                if best.is_none_or(|(_, b, n)| (inside, -c.area()) < (n, -b.area())) {
                    best = Some((angle, c, inside));
                }
            }
        }
    }
    let best = best.map(|(_, b, _)| b);
    // A margin for the residual error of the orientation and of the quantile edges, so that
    // the opening is covered to its corners.
    best.map(|b| Rectangle {
        center: b.center,
        half: b.half.map(|h| h * (1.0 + INNER_MARGIN)),
    })
}

/// Relative growth of each side of an inner rectangle.
const INNER_MARGIN: f64 = 0.001;

/// The inner rectangle with axes u, u-perp about `center` and the number of points inside
/// it, if nearly empty.
fn inner_in_frame(center: DVec2, u: DVec2, p: &[DVec2]) -> Option<(Rectangle, usize)> {
    let v = u.perp();
    let (mut a, mut b) = (0.0f64, 0.0f64);
    for q in p {
        let d = *q - center;
        a = a.max(d.dot(u).abs());
        b = b.max(d.dot(v).abs());
    }
    // Distances from the centre of the points in each side's middle strip: +u, -u, +v, -v.
    let mut sides: [Vec<f64>; 4] = Default::default();
    for q in p {
        let d = *q - center;
        let (s, t) = (d.dot(u), d.dot(v));
        if t.abs() < 0.5 * b {
            sides[if s > 0.0 { 0 } else { 1 }].push(s.abs());
        }
        if s.abs() < 0.5 * a {
            sides[if t > 0.0 { 2 } else { 3 }].push(t.abs());
        }
    }
    // The inner edge of a side: a low quantile of its distances, so that a few stray points
    // inside the opening do not shrink it; the outer edge if the side has no points.
    let mut edge = |k: usize, outer: f64| {
        let d = &mut sides[k];
        if d.is_empty() {
            return outer;
        }
        d.sort_by(f64::total_cmp);
        d[d.len() / INNER_QUANTILE]
    };
    let (hx, lx, hy, ly) = (edge(0, a), -edge(1, a), edge(2, b), -edge(3, b));
    if !(hx > lx && hy > ly) {
        return None;
    }
    let inner = Rectangle {
        center: center + u * ((lx + hx) * 0.5) + v * ((ly + hy) * 0.5),
        half: [u * ((hx - lx) * 0.5), v * ((hy - ly) * 0.5)],
    };
    let inside = p.iter().filter(|q| inner.contains(**q, -1e-6)).count();
    (inside <= p.len() / 50).then_some((inner, inside))
}

/// The inner edge is the 1/INNER_QUANTILE quantile of a side's distances (1%).
const INNER_QUANTILE: usize = 100;

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Rng;

    #[test]
    fn pca_rectangle_spans_points_on_a_rectangle_edge() {
        let mut p = Vec::new();
        for k in 0..100 {
            let t = k as f64 / 100.0;
            p.extend([
                DVec2::new(4.0 * t - 2.0, -1.0),
                DVec2::new(4.0 * t - 2.0, 1.0),
                DVec2::new(-2.0, 2.0 * t - 1.0),
                DVec2::new(2.0, 2.0 * t - 1.0),
            ]);
        }
        let r = pca_rectangle(&p).expect("rectangle");
        let (c, [a, b]) = (r.center, r.half);
        assert!(c.length() < 0.05);
        let (long, short) = if a.length() > b.length() {
            (a, b)
        } else {
            (b, a)
        };
        assert!(
            (long.length() - 2.0).abs() < 0.05 && (short.length() - 1.0).abs() < 0.05,
            "{long} {short}"
        );
    }

    /// Points in the ring between a centred rectangle of half-sizes `inner` and one of
    /// `outer`, or in the ring between circles of those radii.
    fn ring(round: bool, inner: DVec2, outer: DVec2, n: usize) -> Vec<DVec2> {
        let mut rng = Rng::new(11);
        let mut p = Vec::new();
        while p.len() < n {
            let q = DVec2::new(rng.next_f64() * 2.0 - 1.0, rng.next_f64() * 2.0 - 1.0) * outer;
            let keep = if round {
                (q / outer).length() <= 1.0 && (q / inner).length() > 1.0
            } else {
                q.x.abs() > inner.x || q.y.abs() > inner.y
            };
            if keep {
                p.push(q.rotate(DVec2::from_angle(0.3)));
            }
        }
        p
    }

    #[test]
    fn inner_rectangle_finds_a_rectangular_opening_and_refuses_a_round_one() {
        let (hole, outer) = (DVec2::new(0.125, 0.08), DVec2::new(0.131, 0.086));
        let p = ring(false, hole, outer, 3000);
        let r = min_area_rectangle(&p).expect("outer");
        let inner = inner_rectangle(&r, &p).expect("inner");
        let true_area = 4.0 * hole.x * hole.y;
        assert!(
            inner.area() >= true_area * 0.999,
            "{} < {true_area}",
            inner.area()
        );
        assert!(
            inner.area() < true_area * 1.02,
            "{} vs {true_area}",
            inner.area()
        );
        assert!(r.area() > true_area * 1.1);
        // The hole's corners are inside: it is covered.
        for c in [
            hole,
            -hole,
            DVec2::new(hole.x, -hole.y),
            DVec2::new(-hole.x, hole.y),
        ] {
            assert!(inner.contains(c.rotate(DVec2::from_angle(0.3)) * 0.999, 0.0));
        }
        let round = ring(true, DVec2::splat(0.1), DVec2::splat(0.106), 3000);
        let r = min_area_rectangle(&round).expect("outer");
        assert!(inner_rectangle(&r, &round).is_none());
    }

    #[test]
    fn min_area_rectangle_of_a_rotated_rectangle_ring_is_that_rectangle() {
        // Points on and just outside the border of a 0.25 x 0.1 rectangle turned by 0.4 rad:
        // the isotropic-looking ring that defeats PCA's orientation for squares.
        let (c, angle) = (DVec2::new(0.3, -0.2), 0.4f64);
        let (u, v) = (DVec2::from_angle(angle), DVec2::from_angle(angle).perp());
        let mut rng = Rng::new(5);
        let mut p = Vec::new();
        for _ in 0..500 {
            let t = rng.next_f64() * 2.0 - 1.0;
            let (x, y) = match rng.below(4) {
                0 => (t, 1.0),
                1 => (t, -1.0),
                2 => (1.0, t),
                _ => (-1.0, t),
            };
            p.push(c + u * (x * 0.125) + v * (y * 0.05));
        }
        let r = min_area_rectangle(&p).expect("rectangle");
        assert!((r.area() - 0.025).abs() < 0.025 * 0.02, "area {}", r.area());
        assert!((r.center - c).length() < 2e-3);
        let long = if r.half[0].length() > r.half[1].length() {
            r.half[0]
        } else {
            r.half[1]
        };
        assert!(long.normalize().dot(u).abs() > 0.999, "{long}");
        assert!(p.iter().all(|&q| r.contains(q, 1e-9)));
        // A square ring: the rectangle is the square (the covering ellipse would be pi/2 times
        // larger), whatever PCA's arbitrary axes say.
        let sq: Vec<DVec2> = (0..400)
            .map(|k| {
                let t = (k / 4) as f64 / 50.0 - 1.0;
                [
                    DVec2::new(t, 1.0),
                    DVec2::new(t, -1.0),
                    DVec2::new(1.0, t),
                    DVec2::new(-1.0, t),
                ][k % 4]
            })
            .collect();
        let r = min_area_rectangle(&sq).expect("square");
        assert!((r.area() - 4.0).abs() < 1e-9, "{}", r.area());
        assert!(min_area_rectangle(&[DVec2::ZERO, DVec2::X, DVec2::X * 2.0]).is_none());
    }
}
