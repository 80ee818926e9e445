//! Surface relief that tilts the shading normal without moving the surface: pbrt-v4's bump
//! mapping ("texture displacement") and normal maps ("string normalmap", glTF's
//! normalTexture). A shape carries its material's relief ([`crate::Shape::relief`]).

use super::NormalMap;
use crate::interaction::SurfaceInteraction;
use crate::shape::{Shape, ShapeKind, TriangleMesh};
use crate::texture::ImageTexture;
use fenestra_core::{Vec2, Vec3, PI};
use std::sync::Arc;

/// How a surface's shading normal is tilted.
#[derive(Clone, Debug)]
pub enum Relief {
    /// The normal of the surface displaced along its normal by a height texture.
    Bump(BumpMap),
    /// Normals read from a tangent-space map.
    Normals(NormalMap),
}

impl Relief {
    /// Tilts `si`'s shading normal (and tangent) on `shape`; shapes it cannot apply to (a
    /// disk's bump, a mesh without uvs) are left as they are.
    pub fn apply(&self, si: &mut SurfaceInteraction, shape: &Shape) {
        match (self, &shape.kind) {
            (Relief::Bump(b), _) => b.apply(si, shape),
            (Relief::Normals(n), ShapeKind::Mesh(mesh)) => n.apply(si, mesh),
            (Relief::Normals(_), _) => {}
        }
    }
}

/// Bump mapping (Blinn 1978) as pbrt-v4 does it (its `BumpMap`): with p displaced to
/// p + d(u, v) n, the displaced surface's partial derivatives are
///
///   dp'/du = dp/du + (dd/du) n + d dn/du   (and likewise in v),
///
/// dd/du by a forward difference of the texture, and the shading normal becomes
/// dp'/du x dp'/dv, on the side of the geometric normal.
#[derive(Clone, Debug)]
pub struct BumpMap {
    /// Heights (the mean of a texel's channels), in scene units.
    pub displacement: Arc<ImageTexture>,
}

/// The step of the forward differences in u and v: pbrt-v4's when a ray carries no
/// differentials (fenestra's rays never do).
const STEP: f32 = 0.0005;

impl BumpMap {
    fn apply(&self, si: &mut SurfaceInteraction, shape: &Shape) {
        let Some(g) = Derivatives::at(si, shape) else {
            return;
        };
        let height = |uv: Vec2| self.displacement.lookup(uv).average();
        let d = height(si.uv);
        let du = (height(si.uv + Vec2::new(STEP, 0.0)) - d) / STEP;
        let dv = (height(si.uv + Vec2::new(0.0, STEP)) - d) / STEP;
        let dpdu = g.dpdu + si.ns * du + g.dndu * d;
        let dpdv = g.dpdv + si.ns * dv + g.dndv * d;
        let n = dpdu.cross(dpdv).normalize_or_zero();
        if n == Vec3::ZERO || !n.is_finite() {
            return;
        }
        si.ns = if n.dot(si.ng) < 0.0 { -n } else { n };
        si.dpdu = dpdu;
    }
}

/// The shading geometry's partial derivatives in (u, v) where pbrt-v4 would have them.
struct Derivatives {
    dpdu: Vec3,
    dpdv: Vec3,
    dndu: Vec3,
    dndv: Vec3,
}

impl Derivatives {
    fn at(si: &SurfaceInteraction, shape: &Shape) -> Option<Self> {
        match &shape.kind {
            ShapeKind::Mesh(m) => Self::on_mesh(si, m),
            ShapeKind::Sphere { center, radius } => {
                // u = phi / 2pi, v = 1 - theta / pi (pbrt-v4's full sphere), in the sphere's
                // object space, turned back to the world's.
                let turn = shape.orientation.unwrap_or(glam::Mat3::IDENTITY);
                let p = turn.transpose() * (si.p - *center);
                let (r, z) = (*radius, p.z);
                let rxy = (p.x * p.x + p.y * p.y).sqrt();
                let (cos_phi, sin_phi) = if rxy > 0.0 {
                    (p.x / rxy, p.y / rxy)
                } else {
                    (1.0, 0.0)
                };
                let sin_theta = (rxy / r).min(1.0);
                let dpdu = turn * (Vec3::new(-p.y, p.x, 0.0) * (2.0 * PI));
                let dpdv = turn * (Vec3::new(z * cos_phi, z * sin_phi, -r * sin_theta) * -PI);
                Some(Derivatives {
                    dpdu,
                    dpdv,
                    dndu: dpdu / r,
                    dndv: dpdv / r,
                })
            }
            ShapeKind::Disk { .. } => None,
        }
    }

    /// A triangle's, from its uvs: with vertex normals, the tangent made perpendicular to the
    /// shading normal and the bitangent their cross product, and the normals' derivatives;
    /// without, the triangle's own and no curvature (pbrt-v4's `Triangle`).
    fn on_mesh(si: &SurfaceInteraction, m: &TriangleMesh) -> Option<Self> {
        let uvs = m.uvs.as_ref()?;
        let [i0, i1, i2] = m.indices[si.prim].map(|i| i as usize);
        let (duv02, duv12) = (uvs[i0] - uvs[i2], uvs[i1] - uvs[i2]);
        let (dp02, dp12) = (
            m.positions[i0] - m.positions[i2],
            m.positions[i1] - m.positions[i2],
        );
        let det = duv02.x * duv12.y - duv02.y * duv12.x;
        if det.abs() < 1e-20 {
            return None;
        }
        let inv = 1.0 / det;
        let dpdu = (dp02 * duv12.y - dp12 * duv02.y) * inv;
        let dpdv = (dp12 * duv02.x - dp02 * duv12.x) * inv;
        let Some(normals) = &m.normals else {
            return Some(Derivatives {
                dpdu,
                dpdv,
                dndu: Vec3::ZERO,
                dndv: Vec3::ZERO,
            });
        };
        let ts = si.ns.cross(dpdu);
        if ts.length_squared() == 0.0 {
            return None;
        }
        let (dn1, dn2) = (normals[i0] - normals[i2], normals[i1] - normals[i2]);
        Some(Derivatives {
            dpdu: ts.cross(si.ns),
            dpdv: ts,
            dndu: (dn1 * duv12.y - dn2 * duv02.y) * inv,
            dndv: (dn2 * duv02.x - dn1 * duv12.x) * inv,
        })
    }
}
