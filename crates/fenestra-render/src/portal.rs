//! Light portals (seed 000 ch. 4): planar quads, triangles and ellipses through which light
//! enters a scene, sampled by area as in eq. 4.1 with p(l) = 1/N * 1/A_l, and the density of
//! a direction in solid angle for MIS (p(Psi) = p(l) r^2 / cos, zero where cos is zero).

use fenestra_core::{Frame, Vec2, Vec3, PI};

#[derive(Clone, Debug, PartialEq)]
pub enum Portal {
    /// The parallelogram corner + s e1 + t e2, (s, t) in [0, 1]^2.
    Quad {
        corner: Vec3,
        e1: Vec3,
        e2: Vec3,
    },
    Triangle {
        vertices: [Vec3; 3],
    },
    /// The ellipse centre + x a + y b with x^2 + y^2 <= 1 (a, b perpendicular semi-axes).
    Ellipse {
        center: Vec3,
        a: Vec3,
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

    pub fn area(&self) -> f32 {
        match self {
            Portal::Quad { e1, e2, .. } => e1.cross(*e2).length(),
            Portal::Triangle {
                vertices: [p, q, r],
            } => 0.5 * (*q - *p).cross(*r - *p).length(),
            Portal::Ellipse { a, b, .. } => PI * a.length() * b.length(),
        }
    }

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

    /// Distance along the unit direction `d` from `o` to the portal, if the ray crosses it.
    pub fn intersect(&self, o: Vec3, d: Vec3) -> Option<f32> {
        let n = self.normal();
        let denom = n.dot(d);
        if denom.abs() < 1e-12 || n == Vec3::ZERO {
            return None;
        }
        let t = n.dot(self.center() - o) / denom;
        if !(t > 0.0 && t.is_finite()) {
            return None;
        }
        let p = o + d * t;
        let inside = match self {
            Portal::Quad { corner, e1, e2 } => {
                let (s, t) = plane_coordinates(p - *corner, *e1, *e2);
                (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t)
            }
            Portal::Triangle {
                vertices: [a, b, c],
            } => {
                let (s, t) = plane_coordinates(p - *a, *b - *a, *c - *a);
                s >= 0.0 && t >= 0.0 && s + t <= 1.0
            }
            Portal::Ellipse { center, a, b } => {
                let x = (p - *center).dot(*a) / a.length_squared();
                let y = (p - *center).dot(*b) / b.length_squared();
                x * x + y * y <= 1.0
            }
        };
        inside.then_some(t)
    }

    /// The portal's local frame (for plots and exports): normal and in-plane axes.
    pub fn frame(&self) -> Frame {
        Frame::from_normal(self.normal())
    }
}

/// Coordinates (s, t) of `v` in the (not necessarily orthogonal) basis e1, e2 of a plane.
fn plane_coordinates(v: Vec3, e1: Vec3, e2: Vec3) -> (f32, f32) {
    let (a, b, c) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d, e) = (v.dot(e1), v.dot(e2));
    let det = a * c - b * b;
    ((c * d - b * e) / det, (a * e - b * d) / det)
}

/// A set of portals sampled with equal probability each (eq. 4.1).
#[derive(Clone, Debug, Default)]
pub struct Portals {
    pub portals: Vec<Portal>,
}

/// A direction through a portal from a shading point.
#[derive(Clone, Copy, Debug)]
pub struct PortalSample {
    pub wi: Vec3,
    /// Solid-angle density of `wi` over all portals (every portal the ray crosses counts).
    pub pdf: f32,
}

impl Portals {
    pub fn new(portals: Vec<Portal>) -> Self {
        Portals { portals }
    }

    pub fn is_empty(&self) -> bool {
        self.portals.is_empty()
    }

    /// Portals from quads given by their corners (a scene's `portals`: pbrt-v4 "point3
    /// portal" quads, the built-in scenes' openings).
    pub fn from_quads(quads: &[[Vec3; 4]]) -> Self {
        Portals::new(quads.iter().map(|&c| Portal::quad(c)).collect())
    }

    /// Picks a portal with probability 1/N and a point uniformly on it; `None` when the
    /// direction is degenerate (the point seen edge-on).
    pub fn sample(&self, x: Vec3, u_pick: f32, u: Vec2) -> Option<PortalSample> {
        let n = self.portals.len();
        if n == 0 {
            return None;
        }
        let i = ((u_pick * n as f32) as usize).min(n - 1);
        let y = self.portals[i].sample_area(u);
        let wi = (y - x).normalize_or_zero();
        if wi == Vec3::ZERO {
            return None;
        }
        let pdf = self.pdf(x, wi);
        (pdf > 0.0 && pdf.is_finite()).then_some(PortalSample { wi, pdf })
    }

    /// Solid-angle density of sampling direction `wi` at `x`: the sum over the portals the
    /// ray crosses of (1/N)(1/A) t^2 / |cos| (seed 000 ch. 4, p(Psi)).
    pub fn pdf(&self, x: Vec3, wi: Vec3) -> f32 {
        let n = self.portals.len() as f32;
        self.portals
            .iter()
            .filter_map(|p| {
                let t = p.intersect(x, wi)?;
                let cos = p.normal().dot(wi).abs();
                (cos > 0.0).then(|| t * t / (cos * p.area() * n))
            })
            .sum()
    }
}

/// One portal in a portals.json file (schema in docs/portals.md): `kind` "ellipse" with
/// `axes` (two semi-axis vectors), or "quad"/"triangle" with `vertices`; `center`, `normal`
/// and `area` describe it for people and other tools; `photons` and `cluster` say what it
/// was estimated from.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PortalRecord {
    pub kind: String,
    pub center: [f32; 3],
    pub normal: [f32; 3],
    pub area: f32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axes: Option<[[f32; 3]; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertices: Option<Vec<[f32; 3]>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub photons: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cluster: Option<usize>,
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PortalFile {
    pub portals: Vec<PortalRecord>,
}

impl PortalRecord {
    pub fn new(p: &Portal) -> Self {
        let (kind, axes, vertices) = match p {
            Portal::Ellipse { a, b, .. } => ("ellipse", Some([a.to_array(), b.to_array()]), None),
            Portal::Quad { corner, e1, e2 } => (
                "quad",
                None,
                Some(vec![
                    corner.to_array(),
                    (*corner + *e1).to_array(),
                    (*corner + *e1 + *e2).to_array(),
                    (*corner + *e2).to_array(),
                ]),
            ),
            Portal::Triangle { vertices } => (
                "triangle",
                None,
                Some(vertices.map(|v| v.to_array()).to_vec()),
            ),
        };
        PortalRecord {
            kind: kind.into(),
            center: p.center().to_array(),
            normal: p.normal().to_array(),
            area: p.area(),
            axes,
            vertices,
            photons: None,
            cluster: None,
        }
    }

    /// The portal this record describes, or what is wrong with it.
    pub fn portal(&self) -> Result<Portal, String> {
        let v = |a: [f32; 3]| Vec3::from(a);
        let portal = match (self.kind.as_str(), &self.axes, &self.vertices) {
            ("ellipse", Some([a, b]), _) => Portal::Ellipse {
                center: v(self.center),
                a: v(*a),
                b: v(*b),
            },
            ("quad", _, Some(c)) if c.len() == 4 => {
                Portal::quad([v(c[0]), v(c[1]), v(c[2]), v(c[3])])
            }
            ("triangle", _, Some(c)) if c.len() == 3 => Portal::Triangle {
                vertices: [v(c[0]), v(c[1]), v(c[2])],
            },
            ("ellipse", ..) => {
                return Err("an ellipse needs \"axes\": two semi-axis vectors".into())
            }
            ("quad" | "triangle", ..) => {
                return Err(format!(
                    "a {} needs \"vertices\" ({} points)",
                    self.kind,
                    if self.kind == "quad" { 4 } else { 3 }
                ))
            }
            (other, ..) => {
                return Err(format!(
                    "unknown portal kind \"{other}\" (expected ellipse, quad or triangle)"
                ))
            }
        };
        let finite = match &portal {
            Portal::Quad { corner, e1, e2 } => {
                corner.is_finite() && e1.is_finite() && e2.is_finite()
            }
            Portal::Triangle { vertices } => vertices.iter().all(|p| p.is_finite()),
            Portal::Ellipse { center, a, b } => {
                if a.normalize_or_zero().dot(b.normalize_or_zero()).abs() > 1e-3 {
                    return Err("ellipse axes must be perpendicular".into());
                }
                center.is_finite() && a.is_finite() && b.is_finite()
            }
        };
        if !finite || !(portal.area() > 0.0) {
            return Err("a portal needs finite coordinates and a positive area".into());
        }
        Ok(portal)
    }
}

impl Portals {
    /// Reads a portals.json file.
    pub fn read_json(path: &std::path::Path) -> Result<Portals, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let file: PortalFile =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let portals = file
            .portals
            .iter()
            .enumerate()
            .map(|(i, r)| {
                r.portal()
                    .map_err(|e| format!("{}: portal {i}: {e}", path.display()))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Portals::new(portals))
    }

    pub fn to_json(&self) -> PortalFile {
        PortalFile {
            portals: self.portals.iter().map(PortalRecord::new).collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn portal_files_round_trip_and_bad_ones_are_refused() {
        let portals = Portals::new(vec![
            Portal::Ellipse {
                center: Vec3::new(0.0, 0.0, 0.5),
                a: Vec3::X * 0.2,
                b: Vec3::Y * 0.1,
            },
            Portal::quad([Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y]),
            Portal::Triangle {
                vertices: [Vec3::ZERO, Vec3::X, Vec3::Z],
            },
        ]);
        let dir = std::env::temp_dir().join(format!("fenestra-portals-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("p.json");
        std::fs::write(
            &path,
            serde_json::to_string(&portals.to_json()).expect("json"),
        )
        .expect("write");
        assert_eq!(
            Portals::read_json(&path).expect("read").portals,
            portals.portals
        );
        for (bad, why) in [
            (
                r#"{"portals":[{"kind":"disc","center":[0,0,0],"normal":[0,0,1],"area":1}]}"#,
                "unknown portal kind",
            ),
            (
                r#"{"portals":[{"kind":"ellipse","center":[0,0,0],"normal":[0,0,1],"area":1}]}"#,
                "needs \"axes\"",
            ),
            (
                r#"{"portals":[{"kind":"ellipse","center":[0,0,0],"normal":[0,0,1],"area":1,"axes":[[1,0,0],[1,1,0]]}]}"#,
                "perpendicular",
            ),
            (
                r#"{"portals":[{"kind":"quad","center":[0,0,0],"normal":[0,0,1],"area":1,"vertices":[[0,0,0],[1,0,0],[2,0,0],[3,0,0]]}]}"#,
                "positive area",
            ),
            (r#"{"portal":[]}"#, "missing field"),
        ] {
            std::fs::write(&path, bad).expect("write");
            let e = Portals::read_json(&path).expect_err(why);
            assert!(e.contains(why), "{e}");
        }
        let _ = std::fs::remove_dir_all(&dir);
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
        let x = Vec3::new(0.1, -0.2, 0.0);
        let n = 400_000u32;
        let mut sum = 0.0f64;
        for i in 0..n {
            let u = fenestra_core::sampler::hash_u32(i) as f32 / u32::MAX as f32;
            let v = fenestra_core::sampler::hash_u32(i ^ 0x9e37_79b9) as f32 / u32::MAX as f32;
            let d = fenestra_core::warp::square_to_uniform_sphere(Vec2::new(u, v));
            sum += portals.pdf(x, d) as f64 * 4.0 * std::f64::consts::PI;
        }
        let integral = sum / n as f64;
        assert!((integral - 1.0).abs() < 0.02, "{integral}");
    }
}
