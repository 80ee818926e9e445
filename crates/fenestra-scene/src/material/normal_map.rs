//! Tangent-space normal maps (glTF's `normalTexture`, OpenGL's convention: green points
//! towards increasing v, up the image). The tangent frame is each triangle's own, from its
//! uv derivatives (what MikkTSpace gives a flat triangle; across smooth vertex normals it
//! differs slightly, which the file's tangents, when it has them, are meant to fix).

use crate::interaction::SurfaceInteraction;
use crate::shape::TriangleMesh;
use crate::texture::ImageTexture;
use fenestra_core::Vec3;
use std::sync::Arc;

/// A tangent-space normal map: texel (r, g, b) in [0, 1] is the normal
/// ((2r - 1) scale, (2g - 1) scale, 2b - 1) in the frame (tangent, bitangent, normal).
#[derive(Clone, Debug)]
pub struct NormalMap {
    /// Linear texels.
    pub texture: Arc<ImageTexture>,
    /// Scales the map's tangential components.
    pub scale: f32,
}

/// The least cosine between a mapped normal and the geometric one: a map may tilt the
/// shading normal far, never below the surface (where it would shade light from behind).
const MIN_COS: f32 = 0.01;

impl NormalMap {
    /// Tilts `si`'s shading normal on triangle `si.prim` of `mesh` as the map says there
    /// (its tangent follows); a texel with no tangential part leaves `si` as it is, bit for
    /// bit, as does a triangle without uvs.
    pub fn apply(&self, si: &mut SurfaceInteraction, mesh: &TriangleMesh) {
        let Some(uvs) = &mesh.uvs else { return };
        let c = self.texture.lookup(si.uv);
        let (x, y, z) = (
            (2.0 * c.r - 1.0) * self.scale,
            (2.0 * c.g - 1.0) * self.scale,
            2.0 * c.b - 1.0,
        );
        if x == 0.0 && y == 0.0 {
            return;
        }
        let [i0, i1, i2] = mesh.indices[si.prim].map(|i| i as usize);
        let (dp1, dp2) = (
            mesh.positions[i1] - mesh.positions[i0],
            mesh.positions[i2] - mesh.positions[i0],
        );
        let (d1, d2) = (uvs[i1] - uvs[i0], uvs[i2] - uvs[i0]);
        let det = d1.x * d2.y - d1.y * d2.x;
        if det.abs() < 1e-20 {
            return;
        }
        let dpdu = (dp1 * d2.y - dp2 * d1.y) / det;
        let dpdv = (dp2 * d1.x - dp1 * d2.x) / det;
        let ns = si.ns;
        let t = (dpdu - ns * ns.dot(dpdu)).normalize_or_zero();
        if t == Vec3::ZERO {
            return;
        }
        let mut b = ns.cross(t);
        if b.dot(dpdv) < 0.0 {
            b = -b;
        }
        let mut n = (t * x + b * y + ns * z).normalize_or_zero();
        // ns lies in ng's hemisphere; keep the mapped normal there too.
        let cos = n.dot(si.ng);
        if n == Vec3::ZERO || cos < MIN_COS {
            n = (n + si.ng * (MIN_COS - cos)).normalize_or_zero();
        }
        if n != Vec3::ZERO {
            si.ns = n;
            si.dpdu = t;
        }
    }
}
