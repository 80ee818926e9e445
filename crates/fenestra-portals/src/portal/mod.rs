//! Light portals (seed 000 ch. 4): planar quads, triangles and ellipses through which light
//! enters a scene. The seed samples them as in eq. 4.1, p(l) = 1/N * 1/A_l, with the density
//! of a direction in solid angle for MIS (p(Psi) = p(l) r^2 / cos, zero where cos is zero);
//! beyond the seed, rectangles are sampled by solid angle and portals are picked by their
//! estimated contribution at the shading point. Both the seed's and Cycles' rules remain
//! available for comparison.

mod file;
mod spherical_rectangle;

pub use file::{EstimationRecord, PortalFile, PortalRecord};
pub use spherical_rectangle::SphericalRectangle;

use fenestra_core::{Frame, Vec2, Vec3, PI};

/// A planar opening light comes through.
#[derive(Clone, Debug, PartialEq)]
pub enum Portal {
    /// The parallelogram corner + s e1 + t e2, (s, t) in [0, 1]^2.
    Quad {
        /// One corner.
        corner: Vec3,
        /// The edge from `corner` to the second corner.
        e1: Vec3,
        /// The edge from `corner` to the fourth corner.
        e2: Vec3,
    },
    /// A triangle.
    Triangle {
        /// Its corners.
        vertices: [Vec3; 3],
    },
    /// The ellipse centre + x a + y b with x^2 + y^2 <= 1 (a, b perpendicular semi-axes).
    Ellipse {
        /// Its centre.
        center: Vec3,
        /// First semi-axis.
        a: Vec3,
        /// Second semi-axis (perpendicular to `a`).
        b: Vec3,
    },
}

impl Portal {
    /// A quad from four corners in order (the fourth is implied by the first three).
    pub fn quad(corners: [Vec3; 4]) -> Portal {
        Portal::Quad {
            corner: corners[0],
            e1: corners[1] - corners[0],
            e2: corners[3] - corners[0],
        }
    }

    /// "quad", "triangle" or "ellipse" (as in portals.json).
    pub fn kind(&self) -> &'static str {
        match self {
            Portal::Quad { .. } => "quad",
            Portal::Triangle { .. } => "triangle",
            Portal::Ellipse { .. } => "ellipse",
        }
    }

    /// Size in words: edge lengths of a quad, semi-axes of an ellipse.
    pub fn size(&self) -> String {
        match self {
            Portal::Quad { e1, e2, .. } => format!("{:.4} x {:.4} m", e1.length(), e2.length()),
            Portal::Ellipse { a, b, .. } => {
                format!("semi-axes {:.4}, {:.4} m", a.length(), b.length())
            }
            Portal::Triangle { .. } => "triangle".into(),
        }
    }

    /// Unit normal (the sign does not matter: portals pass light both ways).
    pub fn normal(&self) -> Vec3 {
        match self {
            Portal::Quad { e1, e2, .. } => e1.cross(*e2).normalize_or_zero(),
            Portal::Triangle {
                vertices: [p, q, r],
            } => (*q - *p).cross(*r - *p).normalize_or_zero(),
            Portal::Ellipse { a, b, .. } => a.cross(*b).normalize_or_zero(),
        }
    }

    /// Area in m^2.
    pub fn area(&self) -> f32 {
        match self {
            Portal::Quad { e1, e2, .. } => e1.cross(*e2).length(),
            Portal::Triangle {
                vertices: [p, q, r],
            } => 0.5 * (*q - *p).cross(*r - *p).length(),
            Portal::Ellipse { a, b, .. } => PI * a.length() * b.length(),
        }
    }

    /// Centre (centroid of a triangle).
    pub fn center(&self) -> Vec3 {
        match self {
            Portal::Quad { corner, e1, e2 } => *corner + (*e1 + *e2) * 0.5,
            Portal::Triangle {
                vertices: [p, q, r],
            } => (*p + *q + *r) / 3.0,
            Portal::Ellipse { center, .. } => *center,
        }
    }

    /// A point uniformly distributed over the portal's area.
    pub fn sample_area(&self, u: Vec2) -> Vec3 {
        match self {
            Portal::Quad { corner, e1, e2 } => *corner + *e1 * u.x + *e2 * u.y,
            Portal::Triangle {
                vertices: [p, q, r],
            } => {
                let b = fenestra_core::warp::square_to_triangle(u);
                *p * (1.0 - b.x - b.y) + *q * b.x + *r * b.y
            }
            Portal::Ellipse { center, a, b } => {
                // Uniform on the unit disk, stretched: the Jacobian is constant.
                let d = fenestra_core::warp::square_to_disk_concentric(u);
                *center + *a * d.x + *b * d.y
            }
        }
    }

    /// The point of the unit square that [`Portal::sample_area`] maps to `p`, a point of
    /// the portal (or of its plane, clamped into the square).
    pub fn unit_of(&self, p: Vec3) -> Vec2 {
        // The coordinates of p - o along two edges a, b: the dual basis of their Gram matrix.
        let along = |o: Vec3, a: Vec3, b: Vec3| {
            let d = p - o;
            let (aa, ab, bb) = (a.dot(a), a.dot(b), b.dot(b));
            let (da, db) = (d.dot(a), d.dot(b));
            Vec2::new(bb * da - ab * db, aa * db - ab * da) / (aa * bb - ab * ab)
        };
        let unit = match self {
            Portal::Quad { corner, e1, e2 } => along(*corner, *e1, *e2),
            Portal::Triangle {
                vertices: [p0, q, r],
            } => fenestra_core::warp::triangle_to_square(along(*p0, *q - *p0, *r - *p0)),
            Portal::Ellipse { center, a, b } => {
                let d = along(*center, *a, *b);
                fenestra_core::warp::disk_concentric_to_square(d / d.length().max(1.0))
            }
        };
        unit.clamp(Vec2::ZERO, Vec2::ONE)
    }

    /// Distance along the unit direction `d` from `o` to the portal, if the ray crosses it.
    pub fn intersect(&self, o: Vec3, d: Vec3) -> Option<f32> {
        Geometry::new(self).crossing(o, d)
    }

    /// The portal's local frame (for plots and exports): normal and in-plane axes.
    pub fn frame(&self) -> Frame {
        Frame::from_normal(self.normal())
    }
}

/// Relative tolerance of the inside tests: points sampled exactly on an edge must count as
/// inside despite rounding.
const EDGE: f32 = 1e-5;

fenestra_render::choices! {
    /// How a point is chosen on the picked portal.
    pub enum PortalSampling {
        /// Uniform by area (seed 000 eq. 4.1).
        Area = "area",
        /// Uniform in solid angle for rectangles (Urena et al. 2013) where area sampling would
        /// spread the density of directions over them by more than 3x; otherwise, and for
        /// other shapes, by area.
        SolidAngle = "solid-angle",
    }
}

fenestra_render::choices! {
    /// How one of several portals is picked at a shading point.
    pub enum PortalChoice {
        /// 1/N each (seed 000 eq. 4.1).
        Uniform = "uniform",
        /// Uniform among the portals not wholly behind the surface (what Cycles does).
        Facing = "facing",
        /// In proportion to an estimate of each portal's contribution: the solid angle it
        /// subtends (small-portal approximation) times the cosine towards its centre (at least
        /// 0.1 so no visible part is left out), zero when wholly behind the surface.
        Contribution = "contribution",
    }
}

/// A set of portals and how they are sampled.
#[derive(Clone, Debug)]
pub struct Portals {
    portals: Vec<Portal>,
    /// Each portal's geometry, computed once: it is needed for every portal at every vertex.
    geometry: Vec<Geometry>,
    /// How a point is chosen on a portal.
    pub sampling: PortalSampling,
    /// How a portal is picked.
    pub choice: PortalChoice,
}

#[derive(Clone, Copy, Debug)]
struct Geometry {
    normal: Vec3,
    center: Vec3,
    area: f32,
    corners: [Vec3; 4],
    /// Where the in-plane coordinates of a point are measured from, and the dual basis that
    /// gives them as dot products: a parallelogram's or triangle's (s, t) along its edges
    /// from its first corner, an ellipse's (x, y) along its semi-axes from its centre.
    origin: Vec3,
    dual: [Vec3; 2],
    /// For a rectangle, its edges from the first corner (the origin); `None` for other
    /// shapes.
    rectangle: Option<[Vec3; 2]>,
    outline: Outline,
}

/// What the inside test of a portal's plane coordinates is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Outline {
    Quad,
    Triangle,
    Ellipse,
}

impl Geometry {
    fn new(p: &Portal) -> Self {
        // The dual basis of e1, e2: (u, v) with u.e1 = v.e2 = 1, u.e2 = v.e1 = 0 (within
        // the plane).
        let dual = |e1: Vec3, e2: Vec3| {
            let (a, b, c) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
            let det = a * c - b * b;
            [(e1 * c - e2 * b) / det, (e2 * a - e1 * b) / det]
        };
        let (origin, dual, outline) = match *p {
            Portal::Quad { corner, e1, e2 } => (corner, dual(e1, e2), Outline::Quad),
            Portal::Triangle {
                vertices: [a, b, c],
            } => (a, dual(b - a, c - a), Outline::Triangle),
            Portal::Ellipse { center, a, b } => (
                center,
                [a / a.length_squared(), b / b.length_squared()],
                Outline::Ellipse,
            ),
        };
        Geometry {
            normal: p.normal(),
            center: p.center(),
            area: p.area(),
            corners: p.corners(),
            origin,
            dual,
            rectangle: p.rectangle(),
            outline,
        }
    }

    /// Distance along the unit direction `d` from `o` to the portal, if the ray crosses it.
    fn crossing(&self, o: Vec3, d: Vec3) -> Option<f32> {
        let n = self.normal;
        let denom = n.dot(d);
        if denom.abs() < 1e-12 || n == Vec3::ZERO {
            return None;
        }
        let t = n.dot(self.center - o) / denom;
        if !(t > 0.0 && t.is_finite()) {
            return None;
        }
        let q = o + d * t - self.origin;
        let (s, u) = (q.dot(self.dual[0]), q.dot(self.dual[1]));
        let inside = match self.outline {
            Outline::Quad => (-EDGE..=1.0 + EDGE).contains(&s) && (-EDGE..=1.0 + EDGE).contains(&u),
            Outline::Triangle => s >= -EDGE && u >= -EDGE && s + u <= 1.0 + EDGE,
            Outline::Ellipse => s * s + u * u <= 1.0 + EDGE,
        };
        inside.then_some(t)
    }
}

/// A rectangle is sampled by solid angle only where sampling it by area would spread the
/// directions' density by more than this factor: the area density in solid angle is
/// d^3 / (A h) at distance d from a point at height h over the portal's plane, so it varies
/// as the cube of the ratio of the farthest to the nearest point's distance. Farther away,
/// area sampling is almost uniform in solid angle and costs a fraction of Urena's mapping.
/// Measured on the seed-000 boxes (lp_hf, path length 6, 64 spp, MSE over four seeds
/// against 4,096 spp; docs/performance.md), 3 is the most efficient of 1, 1.5, 2, 3, 5:
/// 1.06x (box-hole) and 1.12x (box-4holes) the efficiency of solid angle everywhere.
const AREA_DENSITY_SPREAD: f32 = 3.0;

impl Geometry {
    /// Whether the rectangle is sampled by solid angle at `x` (see [`AREA_DENSITY_SPREAD`]).
    fn by_solid_angle(&self, x: Vec3) -> bool {
        let Some([e1, e2]) = self.rectangle else {
            return false;
        };
        let to = x - self.origin;
        let nearest = self.origin
            + e1 * to.dot(self.dual[0]).clamp(0.0, 1.0)
            + e2 * to.dot(self.dual[1]).clamp(0.0, 1.0);
        let near = (x - nearest).length_squared();
        let far = self
            .corners
            .iter()
            .map(|&c| (c - x).length_squared())
            .fold(0.0, f32::max);
        // (far / near)^(3/2) > spread, without the root.
        let spread = AREA_DENSITY_SPREAD * AREA_DENSITY_SPREAD;
        far * far * far > spread * near * near * near
    }
}

impl Default for Portals {
    fn default() -> Self {
        Portals::new(Vec::new())
    }
}

/// A direction through a portal from a shading point.
#[derive(Clone, Copy, Debug)]
pub struct PortalSample {
    /// Unit direction from the shading point through the portal.
    pub wi: Vec3,
    /// Solid-angle density of `wi` over all portals (every portal the ray crosses counts).
    pub pdf: f32,
}

/// Below this solid angle (sr) a rectangle is sampled by area: Urena's mapping loses
/// precision in f32 for far, tiny rectangles, and area sampling is then as good.
const MIN_SOLID_ANGLE: f32 = 1e-4;

impl Portal {
    /// The edges of a quad with perpendicular edges.
    fn rectangle(&self) -> Option<[Vec3; 2]> {
        match *self {
            Portal::Quad { e1, e2, .. } if e1.dot(e2).abs() <= 1e-4 * e1.length() * e2.length() => {
                Some([e1, e2])
            }
            _ => None,
        }
    }

    /// The spherical rectangle of a rectangular quad seen from `x`, if worth sampling so.
    fn spherical(&self, x: Vec3) -> Option<SphericalRectangle> {
        let Portal::Quad { corner, e1, e2 } = self else {
            return None;
        };
        SphericalRectangle::new(x, *corner, *e1, *e2).filter(|s| s.solid_angle > MIN_SOLID_ANGLE)
    }

    /// Corners of the portal's bounding parallelogram (for the behind-the-surface test).
    pub(crate) fn corners(&self) -> [Vec3; 4] {
        match self {
            Portal::Quad { corner, e1, e2 } => {
                [*corner, *corner + *e1, *corner + *e1 + *e2, *corner + *e2]
            }
            Portal::Triangle {
                vertices: [p, q, r],
            } => [*p, *q, *r, *r],
            Portal::Ellipse { center, a, b } => [
                *center - *a - *b,
                *center + *a - *b,
                *center + *a + *b,
                *center - *a + *b,
            ],
        }
    }
}

/// The surface at a shading point, for choosing portals: its normal when light can only
/// arrive from the front (opaque surfaces), `None` when it transmits.
pub type Side = Option<Vec3>;

/// Pick weights kept per shading point; more portals have theirs evaluated again when needed.
const KEPT_WEIGHTS: usize = 8;

/// The portals' pick weights at a shading point ([`Portals::pick_weights`]): the sample and
/// the densities of later directions from the point all need them.
#[derive(Clone, Copy, Debug, Default)]
pub struct PickWeights {
    x: Vec3,
    side: Side,
    total: f32,
    first: [f32; KEPT_WEIGHTS],
}

impl Portals {
    /// `portals`, sampled by solid angle and picked by contribution.
    pub fn new(portals: Vec<Portal>) -> Self {
        let geometry = portals.iter().map(Geometry::new).collect();
        Portals {
            portals,
            geometry,
            sampling: PortalSampling::SolidAngle,
            choice: PortalChoice::Contribution,
        }
    }

    /// The same portals sampled and picked by other rules.
    pub fn with_strategy(mut self, sampling: PortalSampling, choice: PortalChoice) -> Self {
        self.sampling = sampling;
        self.choice = choice;
        self
    }

    /// Whether there is no portal.
    pub fn is_empty(&self) -> bool {
        self.portals.is_empty()
    }

    /// The portals.
    pub fn portals(&self) -> &[Portal] {
        &self.portals
    }

    /// Portals from quads given by their corners (a scene's `portals`: pbrt-v4 "point3
    /// portal" quads, the built-in scenes' openings).
    pub fn from_quads(quads: &[[Vec3; 4]]) -> Self {
        Portals::new(quads.iter().map(|&c| Portal::quad(c)).collect())
    }

    /// The unnormalised probability of picking portal `p` at `x`. The contribution estimate
    /// uses the small-portal solid angle A |cos| / d^2 (capped at 2 pi): it only steers the
    /// choice, and is cheap enough to evaluate for every portal at every vertex.
    fn weight(&self, g: &Geometry, x: Vec3, side: Side) -> f32 {
        let behind = |n: Vec3| g.corners.iter().all(|&c| (c - x).dot(n) <= 0.0);
        match self.choice {
            PortalChoice::Uniform => 1.0,
            PortalChoice::Facing => match side {
                Some(n) if behind(n) => 0.0,
                _ => 1.0,
            },
            PortalChoice::Contribution => {
                if side.is_some_and(behind) {
                    return 0.0;
                }
                let to_center = g.center - x;
                let d2 = to_center.length_squared();
                let d = d2.sqrt();
                let omega = (g.area * g.normal.dot(to_center).abs() / (d2 * d)).min(2.0 * PI);
                let cos = side.map_or(1.0, |n| n.dot(to_center) / d).max(0.1);
                omega * cos
            }
        }
    }

    /// The pick weights at `x` on the surface `side`, computed once per shading point and
    /// passed to [`Portals::sample`] and [`Portals::pdf`].
    pub fn pick_weights(&self, x: Vec3, side: Side) -> PickWeights {
        let mut w = PickWeights {
            x,
            side,
            total: 0.0,
            first: [0.0; KEPT_WEIGHTS],
        };
        for (k, g) in self.geometry.iter().enumerate() {
            let weight = self.weight(g, x, side);
            if k < KEPT_WEIGHTS {
                w.first[k] = weight;
            }
            w.total += weight;
        }
        w
    }

    /// Whether portal `g` is sampled by solid angle from `x`.
    fn by_solid_angle(&self, g: &Geometry, x: Vec3) -> bool {
        self.sampling == PortalSampling::SolidAngle && g.by_solid_angle(x)
    }

    /// Portal `k`'s pick weight at `w`'s point: kept, or evaluated again past the first
    /// [`KEPT_WEIGHTS`] portals.
    fn weight_at(&self, w: &PickWeights, k: usize, g: &Geometry) -> f32 {
        match w.first.get(k) {
            Some(&weight) => weight,
            None => self.weight(g, w.x, w.side),
        }
    }

    /// Picks a portal (by the choice rule) and a point on it (by the sampling rule); `None`
    /// when no portal can be seen or the direction is degenerate.
    pub fn sample(&self, weights: &PickWeights, u_pick: f32, u: Vec2) -> Option<PortalSample> {
        let x = weights.x;
        if !(weights.total > 0.0) {
            return None;
        }
        // Walk the weights to the picked one (no allocation per sample).
        let target = u_pick * weights.total;
        let mut acc = 0.0;
        let mut picked = None;
        for (k, (p, g)) in self.portals.iter().zip(&self.geometry).enumerate() {
            let w = self.weight_at(weights, k, g);
            acc += w;
            if w > 0.0 {
                picked = Some((k, p, g));
                if target < acc {
                    break;
                }
            }
        }
        let (k, portal, g) = picked?;
        let spherical = self
            .by_solid_angle(g, x)
            .then(|| portal.spherical(x))
            .flatten();
        let y = match spherical {
            Some(s) => s.sample(u),
            None => portal.sample_area(u),
        };
        let wi = (y - x).normalize_or_zero();
        if wi == Vec3::ZERO {
            return None;
        }
        let pdf = self.pdf_knowing(weights, wi, Some((k, spherical)));
        (pdf > 0.0 && pdf.is_finite()).then_some(PortalSample { wi, pdf })
    }

    /// Solid-angle density of sampling direction `wi` at `x`: the sum over the portals the
    /// ray crosses of the pick probability times that portal's density (area sampling:
    /// (1/A) t^2 / |cos|, seed 000 ch. 4, p(Psi); solid-angle sampling: 1/S), from the point
    /// of `weights`.
    pub fn pdf(&self, weights: &PickWeights, wi: Vec3) -> f32 {
        self.pdf_knowing(weights, wi, None)
    }

    /// [`Portals::pdf`], knowing how portal `k` is sampled at `x` (by [`Portals::sample`],
    /// which picked it): by its spherical rectangle, or by area when `None`.
    fn pdf_knowing(
        &self,
        weights: &PickWeights,
        wi: Vec3,
        known: Option<(usize, Option<SphericalRectangle>)>,
    ) -> f32 {
        let (x, total) = (weights.x, weights.total);
        if !(total > 0.0) {
            return 0.0;
        }
        self.portals
            .iter()
            .zip(&self.geometry)
            .enumerate()
            .filter_map(|(k, (p, g))| {
                let t = g.crossing(x, wi)?;
                let pick = self.weight_at(weights, k, g) / total;
                if pick == 0.0 {
                    return Some(0.0);
                }
                let spherical = match known {
                    Some((j, s)) if j == k => s,
                    _ => self.by_solid_angle(g, x).then(|| p.spherical(x)).flatten(),
                };
                if let Some(s) = spherical {
                    return Some(pick / s.solid_angle);
                }
                let cos = g.normal.dot(wi).abs();
                (cos > 0.0).then(|| pick * t * t / (cos * g.area))
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_of_inverts_sample_area() {
        let shapes = [
            Portal::Quad {
                corner: Vec3::new(0.3, -1.0, 2.0),
                e1: Vec3::new(1.5, 0.2, 0.0),
                e2: Vec3::new(0.4, 0.1, 0.9),
            },
            Portal::Triangle {
                vertices: [
                    Vec3::ZERO,
                    Vec3::new(2.0, 0.5, 0.0),
                    Vec3::new(0.3, 0.2, 1.7),
                ],
            },
            Portal::Ellipse {
                center: Vec3::new(1.0, 2.0, 3.0),
                a: Vec3::new(0.0, 0.8, 0.0),
                b: Vec3::new(0.0, 0.0, 0.3),
            },
        ];
        for portal in &shapes {
            for i in 0..32 {
                for j in 0..32 {
                    let u = Vec2::new((i as f32 + 0.5) / 32.0, (j as f32 + 0.5) / 32.0);
                    let back = portal.unit_of(portal.sample_area(u));
                    assert!((back - u).length() < 1e-4, "{portal:?}: {u} as {back}");
                }
            }
        }
    }

    #[test]
    fn ellipse_samples_are_uniform_over_the_area() {
        // Chi-square over 5 rings x 8 sectors of equal area in the ellipse's own coordinates
        // (x^2 + y^2 uniform in [0, 1] and the angle uniform for a uniform density).
        let (c, a) = (Vec3::new(0.2, -0.1, 0.5), Vec3::new(0.6, 0.3, 0.0));
        // A tilted second semi-axis, made perpendicular to a.
        let b = Vec3::new(-0.1, 0.2, 0.4);
        let b = b - a * (a.dot(b) / a.length_squared());
        let e = Portal::Ellipse { center: c, a, b };
        let (rings, sectors, n) = (5usize, 8usize, 80_000u32);
        let mut counts = vec![0f64; rings * sectors];
        for i in 0..n {
            let u = Vec2::new(
                fenestra_core::sampler::hash_u32(i) as f32 / 4_294_967_296.0,
                fenestra_core::sampler::hash_u32(i ^ 0x2545_f491) as f32 / 4_294_967_296.0,
            );
            let d = e.sample_area(u) - c;
            let (x, y) = (d.dot(a) / a.length_squared(), d.dot(b) / b.length_squared());
            let r2 = x * x + y * y;
            assert!(r2 <= 1.0 + 1e-4, "outside: {r2}");
            let ring = ((r2 * rings as f32) as usize).min(rings - 1);
            let angle = y.atan2(x).rem_euclid(2.0 * PI);
            let sector = ((angle / (2.0 * PI) * sectors as f32) as usize).min(sectors - 1);
            counts[ring * sectors + sector] += 1.0;
        }
        let expected = vec![n as f64 / (rings * sectors) as f64; rings * sectors];
        let fit = fenestra_eval::chi2::chi2(&counts, &expected, 0.0).expect("same bins");
        assert!(fit.p_value > 1e-3, "{fit:?}");
    }

    #[test]
    fn shapes_have_their_areas_and_are_hit_inside_only() {
        let q = Portal::quad([
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(2.0, 0.0, 1.0),
            Vec3::new(2.0, 1.0, 1.0),
            Vec3::new(0.0, 1.0, 1.0),
        ]);
        assert!((q.area() - 2.0).abs() < 1e-6);
        assert!(q.intersect(Vec3::new(1.0, 0.5, 0.0), Vec3::Z).is_some());
        assert!(q.intersect(Vec3::new(2.5, 0.5, 0.0), Vec3::Z).is_none());
        assert!(
            q.intersect(Vec3::new(1.0, 0.5, 2.0), Vec3::Z).is_none(),
            "behind the origin"
        );
        let e = Portal::Ellipse {
            center: Vec3::ZERO,
            a: Vec3::X * 2.0,
            b: Vec3::Y,
        };
        assert!((e.area() - 2.0 * PI).abs() < 1e-5);
        assert!(e.intersect(Vec3::new(1.9, 0.0, -1.0), Vec3::Z).is_some());
        assert!(e.intersect(Vec3::new(1.5, 0.8, -1.0), Vec3::Z).is_none());
    }

    #[test]
    fn pdf_integrates_to_one_over_the_directions_through_the_portals() {
        // Monte Carlo over the sphere: the integral of the density is 1 when every sampled
        // direction can be produced (x sees all portals from the front).
        let portals = Portals::new(vec![
            Portal::quad([
                Vec3::new(-0.5, -0.5, 1.0),
                Vec3::new(0.5, -0.5, 1.0),
                Vec3::new(0.5, 0.5, 1.0),
                Vec3::new(-0.5, 0.5, 1.0),
            ]),
            Portal::Ellipse {
                center: Vec3::new(1.5, 0.0, 1.5),
                a: Vec3::X * 0.4,
                b: Vec3::Y * 0.2,
            },
            Portal::Triangle {
                vertices: [
                    Vec3::new(-2.0, 0.0, 0.5),
                    Vec3::new(-1.0, 0.0, 0.5),
                    Vec3::new(-1.5, 1.0, 0.8),
                ],
            },
        ]);
        // The square sampled by area from afar, by solid angle from near it.
        let (far, near) = (Vec3::new(0.1, -0.2, 0.0), Vec3::new(0.1, -0.2, 0.3));
        assert!(!portals.geometry[0].by_solid_angle(far));
        assert!(portals.geometry[0].by_solid_angle(near));
        let uniform =
            |i: u32, salt: u32| fenestra_core::sampler::hash_u32(i ^ salt) as f32 / 4_294_967_296.0;
        for (x, sampling) in [
            (far, PortalSampling::Area),
            (far, PortalSampling::SolidAngle),
            (near, PortalSampling::SolidAngle),
        ] {
            for choice in [
                PortalChoice::Uniform,
                PortalChoice::Facing,
                PortalChoice::Contribution,
            ] {
                // A surface tilted so that the triangle portal lies wholly behind it.
                for side in [None, Some(Vec3::new(0.6, 0.0, 0.8))] {
                    let portals = portals.clone().with_strategy(sampling, choice);
                    let n = 400_000u32;
                    let mut sum = 0.0f64;
                    for i in 0..n {
                        let d = fenestra_core::warp::square_to_uniform_sphere(Vec2::new(
                            uniform(i, 0),
                            uniform(i, 0x9e37_79b9),
                        ));
                        let weights = portals.pick_weights(x, side);
                        sum += portals.pdf(&weights, d) as f64 * 4.0 * std::f64::consts::PI;
                    }
                    let integral = sum / n as f64;
                    let what = format!("{sampling:?} at {x}, {choice:?}, side {side:?}");
                    assert!((integral - 1.0).abs() < 0.02, "{what}: {integral}");
                    // Sampled directions carry the density pdf() gives them.
                    for i in 0..200 {
                        let u = Vec2::new(uniform(i, 7), uniform(i, 8));
                        let weights = portals.pick_weights(x, side);
                        let Some(s) = portals.sample(&weights, uniform(i, 9), u) else {
                            panic!("{what}: no sample for {u} {}", uniform(i, 9));
                        };
                        let p = portals.pdf(&weights, s.wi);
                        assert!((s.pdf / p - 1.0).abs() < 1e-4, "{what}: {} vs {p}", s.pdf);
                    }
                }
            }
        }
    }
}
