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

/// Offsets `p` along the geometric normal `ng` to the side of `w`, so that a ray leaving the
/// surface does not hit it again through floating-point error (a simpler form of pbrt's error
/// bounds). The offset is about 16 ulps of the coordinates: hit points are reconstructed to
/// a few ulps, and a larger offset would bias MIS in concave corners, where a ray from the
/// offset origin finds a different emitter point than the one the light pdf is computed for.
pub fn offset_origin(p: Vec3, ng: Vec3, w: Vec3) -> Vec3 {
    let eps = 2e-6 * (1.0 + p.abs().max_element());
    if ng.dot(w) >= 0.0 {
        p + ng * eps
    } else {
        p - ng * eps
    }
}
