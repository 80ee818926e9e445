//! Orthonormal shading frames.

use glam::Vec3;

/// An orthonormal basis (s, t, n); local coordinates have the normal along +z.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// First tangent.
    pub s: Vec3,
    /// Second tangent.
    pub t: Vec3,
    /// Normal (local +z).
    pub n: Vec3,
}

impl Frame {
    /// Builds a frame around a unit normal (Duff et al. 2017, branchless ONB).
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Frame { s, t, n }
    }

    /// Builds a frame from a unit normal and a tangent hint (for anisotropic materials); the
    /// tangent is orthogonalised against the normal, falling back to `from_normal`.
    pub fn from_normal_tangent(n: Vec3, tangent: Vec3) -> Self {
        // The tangent's length is the surface's scale, so the test for a tangent along the
        // normal is relative to it. Tangents of ordinary length are used as they are (one
        // square root less on every shading point); others are normalised first.
        let t2 = tangent.length_squared();
        let tangent = if t2 > 1e-30 && t2 < 1e30 {
            tangent
        } else {
            crate::ray::robust_normalize(tangent)
        };
        let s = tangent - n * n.dot(tangent);
        let s2 = s.length_squared();
        if !s2.is_finite() || s2 <= 1e-12 * tangent.length_squared() {
            return Frame::from_normal(n);
        }
        let s = s * (1.0 / s2.sqrt());
        Frame {
            s,
            t: n.cross(s),
            n,
        }
    }

    /// `v` (world) in this frame's coordinates.
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }
    /// `v` (in this frame's coordinates) in world coordinates.
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_orthonormal_for_all_hemispheres() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(0.3, -0.4, -0.866).normalize(),
        ] {
            let f = Frame::from_normal(n);
            assert!((f.s.length() - 1.0).abs() < 1e-5);
            assert!((f.t.length() - 1.0).abs() < 1e-5);
            assert!(f.s.dot(f.t).abs() < 1e-5 && f.s.dot(n).abs() < 1e-5);
            assert!((f.s.cross(f.t) - n).length() < 1e-5, "right-handed");
            let v = Vec3::new(0.2, 0.5, -0.1);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-5);
        }
    }
}
