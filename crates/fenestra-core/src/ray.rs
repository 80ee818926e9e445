//! Rays and robust spawning of secondary rays off surfaces.

use glam::Vec3;

/// A ray: origin and unit direction.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    /// Origin.
    pub o: Vec3,
    /// Unit direction.
    pub d: Vec3,
}

impl Ray {
    /// The ray from `o` along the unit direction `d`.
    pub fn new(o: Vec3, d: Vec3) -> Self {
        Ray { o, d }
    }
    /// The point at distance `t` along the ray.
    pub fn at(&self, t: f32) -> Vec3 {
        self.o + self.d * t
    }
}

/// Relative size of the offset of a ray leaving a surface: about 16 ulps of f32. Hit points
/// are reconstructed to a few ulps of the values they are computed from, and a larger offset
/// would bias MIS in concave corners, where a ray from the offset origin finds a different
/// emitter point than the one the light pdf is computed for.
pub const OFFSET_ULPS: f32 = 2e-6;

/// How far a point computed from values of magnitude up to `scale` (per coordinate) may lie
/// off its surface through rounding: the distance to offset a ray leaving it.
pub fn offset_distance(scale: f32) -> f32 {
    OFFSET_ULPS * scale
}

/// Offsets `p` by `distance` along the geometric normal `ng`, to the side of `w`, so that a
/// ray leaving the surface does not hit it again through floating-point error (pbrt's error
/// bounds in a simpler form). `distance` comes from [`offset_distance`] of the magnitudes `p`
/// was computed from, so the offset is relative and a scene looks the same at any scale.
pub fn offset_origin(p: Vec3, ng: Vec3, w: Vec3, distance: f32) -> Vec3 {
    if ng.dot(w) >= 0.0 {
        p + ng * distance
    } else {
        p - ng * distance
    }
}

/// `v`'s length, without overflow or underflow for any finite `v` (scaled by its largest
/// component first).
pub fn robust_length(v: Vec3) -> f32 {
    let m = v.abs().max_element();
    if m > 0.0 && m.is_finite() {
        m * (v / m).length()
    } else {
        m
    }
}

/// `v` of unit length, or zero for a zero or non-finite `v`; without the overflow of
/// `normalize` for vectors longer than about 1e19 or the underflow below about 1e-19.
pub fn robust_normalize(v: Vec3) -> Vec3 {
    // Most vectors are far from both ends: their squared length is exact enough to use as
    // it is (the slow path costs a division more on every hit point and shading frame).
    let l2 = v.length_squared();
    if l2 > 1e-30 && l2 < 1e30 {
        return v * (1.0 / l2.sqrt());
    }
    let m = v.abs().max_element();
    if m > 0.0 && m.is_finite() {
        (v / m).normalize_or_zero()
    } else {
        Vec3::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_and_directions_hold_at_every_scale() {
        let v = Vec3::new(3.0, -4.0, 12.0);
        for s in [1e-30f32, 1e-12, 1.0, 1e12, 1e25] {
            let w = v * s;
            assert!((robust_length(w) / (13.0 * s) - 1.0).abs() < 1e-6, "{s}");
            assert!((robust_normalize(w) - v / 13.0).length() < 1e-6, "{s}");
        }
        assert_eq!(robust_normalize(Vec3::ZERO), Vec3::ZERO);
        assert_eq!(
            robust_normalize(Vec3::new(f32::INFINITY, 0.0, 0.0)),
            Vec3::ZERO
        );
        // glam's own normalisation loses both ends.
        assert_eq!((v * 1e25).normalize_or_zero(), Vec3::ZERO);
    }
}
