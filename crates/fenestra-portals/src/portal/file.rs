//! portals.json (schema in docs/portals.md): reading with validation, writing.

use super::{Portal, Portals};
use crate::error::PortalError;
use crate::estimate::{EstimateParams, Timings};
use crate::photon::Deposit;
use fenestra_core::fs::write_text_atomically;
use fenestra_core::Vec3;
use std::path::Path;

/// One portal in a portals.json file (schema in docs/portals.md): `kind` "ellipse" with
/// `axes` (two semi-axis vectors), or "quad"/"triangle" with `vertices`; `center`, `normal`
/// and `area` describe it for people and other tools; `photons` and `cluster` say what it
/// was estimated from.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PortalRecord {
    /// "quad", "triangle" or "ellipse".
    pub kind: String,
    /// Centre.
    pub center: [f32; 3],
    /// Unit normal (either side).
    pub normal: [f32; 3],
    /// Area in m^2.
    pub area: f32,
    /// An ellipse's two semi-axis vectors.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axes: Option<[[f32; 3]; 2]>,
    /// A quad's four or a triangle's three corners, in order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertices: Option<Vec<[f32; 3]>>,
    /// Photons of the cluster it was fitted to.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub photons: Option<usize>,
    /// That cluster's index (largest first).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cluster: Option<usize>,
}

/// A portals.json document: the portals, and how they were estimated when they were.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PortalFile {
    /// The portals.
    pub portals: Vec<PortalRecord>,
    /// How the portals were estimated (written by `fenestra portals`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub estimation: Option<EstimationRecord>,
}

/// How an estimate was made and what it took.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct EstimationRecord {
    /// The scene estimated from, as given on the command line.
    pub scene: String,
    /// The pipeline's parameters.
    pub parameters: EstimateParams,
    /// Photons gathered.
    pub photons: usize,
    /// Beams traced.
    pub beams: u64,
    /// Rays traced.
    pub rays: u64,
    /// Where photons were deposited.
    pub deposit: Deposit,
    /// Whether photon tracing was stopped by the user.
    pub interrupted: bool,
    /// Whether photon tracing stopped early because the portals had settled.
    #[serde(default)]
    pub settled: bool,
    /// Whether photon tracing stopped at its time limit (the photons then depend on the
    /// machine's speed).
    #[serde(default)]
    pub timed_out: bool,
    /// Clusters found.
    pub clusters: usize,
    /// Seconds per stage.
    pub time_s: Timings,
}

impl PortalRecord {
    /// The record of `p`.
    pub fn new(p: &Portal) -> Self {
        let (axes, vertices) = match p {
            Portal::Ellipse { a, b, .. } => (Some([a.to_array(), b.to_array()]), None),
            Portal::Quad { corner, e1, e2 } => (
                None,
                Some(vec![
                    corner.to_array(),
                    (*corner + *e1).to_array(),
                    (*corner + *e1 + *e2).to_array(),
                    (*corner + *e2).to_array(),
                ]),
            ),
            Portal::Triangle { vertices } => (None, Some(vertices.map(|v| v.to_array()).to_vec())),
        };
        PortalRecord {
            kind: p.kind().into(),
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
    fn portal(&self) -> Result<Portal, RecordError> {
        let v = |a: [f32; 3]| Vec3::from(a);
        let portal = match (self.kind.as_str(), &self.axes, &self.vertices) {
            ("ellipse", Some([a, b]), _) => Portal::Ellipse {
                center: v(self.center),
                a: v(*a),
                b: v(*b),
            },
            ("quad", _, Some(c)) if c.len() == 4 => {
                let corners = [v(c[0]), v(c[1]), v(c[2]), v(c[3])];
                // The third corner is implied by the others: a quad that is not a
                // parallelogram would silently become another portal.
                let implied = corners[1] + corners[3] - corners[0];
                let size = (corners[1] - corners[0])
                    .length()
                    .max((corners[3] - corners[0]).length());
                let off = (corners[2] - implied).length();
                if !(off <= 1e-4 * size) {
                    return Err(RecordError::NotParallelogram { off });
                }
                Portal::quad(corners)
            }
            ("triangle", _, Some(c)) if c.len() == 3 => Portal::Triangle {
                vertices: [v(c[0]), v(c[1]), v(c[2])],
            },
            ("ellipse", ..) => return Err(RecordError::Axes),
            ("quad", ..) => {
                return Err(RecordError::Vertices {
                    kind: "quad",
                    points: 4,
                })
            }
            ("triangle", ..) => {
                return Err(RecordError::Vertices {
                    kind: "triangle",
                    points: 3,
                })
            }
            (other, ..) => return Err(RecordError::Kind(other.to_string())),
        };
        let finite = match &portal {
            Portal::Quad { corner, e1, e2 } => {
                corner.is_finite() && e1.is_finite() && e2.is_finite()
            }
            Portal::Triangle { vertices } => vertices.iter().all(|p| p.is_finite()),
            Portal::Ellipse { center, a, b } => {
                if a.normalize_or_zero().dot(b.normalize_or_zero()).abs() > 1e-3 {
                    return Err(RecordError::Perpendicular);
                }
                center.is_finite() && a.is_finite() && b.is_finite()
            }
        };
        let extent = portal
            .corners()
            .iter()
            .fold(0.0f32, |e, c| e.max(c.abs().max_element()));
        if let Some(what) = fenestra_scene::extent::extent_error(extent).filter(|_| finite) {
            return Err(RecordError::Extent(what));
        }
        if !finite || !portal.area().is_normal() || portal.area() < 0.0 {
            return Err(RecordError::Degenerate);
        }
        Ok(portal)
    }
}

/// What is wrong with a portals.json record.
#[derive(Debug, thiserror::Error)]
enum RecordError {
    #[error("a quad's vertices must form a parallelogram in order (the third is {off:e} m from where the others put it)")]
    NotParallelogram { off: f32 },
    #[error("an ellipse needs \"axes\": two semi-axis vectors")]
    Axes,
    #[error("a {kind} needs \"vertices\" ({points} points)")]
    Vertices { kind: &'static str, points: usize },
    #[error("unknown portal kind \"{0}\" (expected ellipse, quad or triangle)")]
    Kind(String),
    #[error("ellipse axes must be perpendicular")]
    Perpendicular,
    #[error("{0}")]
    Extent(String),
    #[error("a portal needs finite coordinates and a positive area")]
    Degenerate,
}

impl PortalFile {
    /// Reads a portals.json file (the portals are checked by [`PortalFile::portals`]).
    pub fn read(path: &Path) -> Result<PortalFile, PortalError> {
        let bad = |reason: String| PortalError::File {
            path: path.to_path_buf(),
            reason,
        };
        let text = std::fs::read_to_string(path).map_err(|e| bad(e.to_string()))?;
        serde_json::from_str(&text).map_err(|e| bad(e.to_string()))
    }

    /// Writes the document as pretty JSON, atomically.
    pub fn write(&self, path: &Path) -> Result<(), PortalError> {
        let text = serde_json::to_string_pretty(self)
            .map_err(|e| fenestra_core::fs::WriteError::new(path, e))?;
        Ok(write_text_atomically(path, &(text + "\n"))?)
    }

    /// The portals the records describe; `path` names the file in errors.
    pub fn portals(&self, path: &Path) -> Result<Portals, PortalError> {
        let portals = self
            .portals
            .iter()
            .enumerate()
            .map(|(i, r)| {
                r.portal().map_err(|e| PortalError::File {
                    path: path.to_path_buf(),
                    reason: format!("portal {i}: {e}"),
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Portals::new(portals))
    }
}

impl Portals {
    /// Reads the portals of a portals.json file.
    pub fn read_json(path: &Path) -> Result<Portals, PortalError> {
        PortalFile::read(path)?.portals(path)
    }

    /// The portals.json document of these portals.
    pub fn to_file(&self) -> PortalFile {
        PortalFile {
            portals: self.portals().iter().map(PortalRecord::new).collect(),
            estimation: None,
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
        portals.to_file().write(&path).expect("write");
        assert_eq!(
            Portals::read_json(&path).expect("read").portals(),
            portals.portals()
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
                r#"{"portals":[{"kind":"quad","center":[0,0,0],"normal":[0,0,1],"area":1,"vertices":[[0,0,0],[1,0,0],[2,0,0],[1,0,0]]}]}"#,
                "positive area",
            ),
            (r#"{"portal":[]}"#, "missing field"),
            (
                r#"{"portals":[{"kind":"quad","center":[0,0,0],"normal":[0,0,1],"area":1,"vertices":[[0,0,0],[1,0,0],[0.5,1,0],[0,1,0]]}]}"#,
                "must form a parallelogram",
            ),
            (
                r#"{"portals":[{"kind":"quad","center":[0,0,0],"normal":[0,0,1],"area":1,"vertices":[[0,0,0],[1e-20,0,0],[1e-20,1e-20,0],[0,1e-20,0]]}]}"#,
                "positive area",
            ),
            (
                r#"{"portals":[{"kind":"quad","center":[0,0,0],"normal":[0,0,1],"area":1,"vertices":[[0,0,0],[1e20,0,0],[1e20,1,0],[0,1,0]]}]}"#,
                "beyond the 1e12 m",
            ),
        ] {
            std::fs::write(&path, bad).expect("write");
            let e = Portals::read_json(&path).expect_err(why).to_string();
            assert!(e.contains(why), "{e}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
