//! Perspective pinhole camera.

use fenestra_core::{Ray, Vec2, Vec3};

#[derive(Clone, Debug)]
pub struct Camera {
    pub position: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y: f32,
}

impl Camera {
    /// A camera at `eye` looking at `target`, with `up` giving the image's vertical and a
    /// vertical field of view of `fov_y` degrees. Errors on degenerate input.
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3, fov_y: f32) -> Result<Self, String> {
        let forward = (target - eye).normalize_or_zero();
        let right = forward.cross(up).normalize_or_zero();
        if forward == Vec3::ZERO || right == Vec3::ZERO || !eye.is_finite() {
            return Err(format!(
                "degenerate camera: eye {eye}, target {target}, up {up}"
            ));
        }
        if !(fov_y > 0.0 && fov_y < 180.0) {
            return Err(format!("field of view {fov_y} must be in (0, 180) degrees"));
        }
        Ok(Camera {
            position: eye,
            forward,
            right,
            up: right.cross(forward),
            fov_y,
        })
    }

    pub fn forward(&self) -> Vec3 {
        self.forward
    }

    /// The primary ray through film position `film` (pixels, x right, y down, (0,0) the top
    /// left corner of the image) on a `width` x `height` film.
    pub fn generate_ray(&self, film: Vec2, width: u32, height: u32) -> Ray {
        let tan_half = (0.5 * self.fov_y.to_radians()).tan();
        let aspect = width as f32 / height as f32;
        let sx = (2.0 * film.x / width as f32 - 1.0) * tan_half * aspect;
        let sy = (1.0 - 2.0 * film.y / height as f32) * tan_half;
        Ray::new(
            self.position,
            (self.forward + self.right * sx + self.up * sy).normalize(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn image_axes_follow_right_and_up() {
        let c = Camera::look_at(Vec3::ZERO, Vec3::Y, Vec3::Z, 90.0).expect("camera");
        let centre = c.generate_ray(Vec2::new(50.0, 50.0), 100, 100);
        assert!((centre.d - Vec3::Y).length() < 1e-6);
        // Right edge middle: 45 degrees to the right (+x for a camera looking along +y, z up).
        let right = c.generate_ray(Vec2::new(100.0, 50.0), 100, 100);
        assert!((right.d - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-5);
        let top = c.generate_ray(Vec2::new(50.0, 0.0), 100, 100);
        assert!(top.d.z > 0.7);
        assert!(Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Z, 60.0).is_err());
        assert!(Camera::look_at(Vec3::ZERO, Vec3::Y, Vec3::Z, 0.0).is_err());
    }
}
