//! Perspective pinhole camera.

use crate::filter::PixelFilter;
use fenestra_core::white_balance;
use fenestra_core::{Ray, Vec2, Vec3};
use glam::Mat3;

/// How the field of view is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FieldOfView {
    /// Vertical angle in degrees (fenestra's built-in scenes).
    Vertical(f32),
    /// Angle in degrees across the shorter image axis (pbrt-v4's "fov").
    ShorterAxis(f32),
}

/// Where a point appears on the film, for paths that reach the camera from the scene (light
/// tracing): the film position and the density with which camera rays take its direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// Film position in pixels (x right, y down, (0, 0) the image's top left corner), as
    /// [`Camera::generate_ray`] takes it.
    pub film: Vec2,
    /// Unit direction from the pinhole to the point.
    pub dir: Vec3,
    /// Distance from the pinhole to the point.
    pub distance: f32,
    /// Solid-angle density of `dir` for film positions of density 1 per square pixel: a
    /// camera sample drawn with density q (per square pixel) takes `dir` with density
    /// q * `dir_pdf`, and a light path's vertex seen by the pixel counts with that weight.
    pub dir_pdf: f32,
}

/// A pinhole camera.
#[derive(Clone, Debug)]
pub struct Camera {
    /// The pinhole.
    pub position: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    /// The field of view.
    pub fov: FieldOfView,
    /// pbrt's "screenwindow" (x0, x1, y0, y1) in units of tan(fov / 2); the default spans
    /// the field of view with the image's aspect ratio.
    pub screen_window: Option<[f32; 4]>,
    /// The pixel filter camera samples are drawn from (a uniform point of the pixel unless
    /// the scene says otherwise).
    pub filter: PixelFilter,
    /// The film's white balance (pbrt-v4's Film "whitebalance"): the colour temperature in
    /// kelvin of the illuminant whose white the image shows as white; None leaves the
    /// colours as rendered.
    pub white_balance: Option<f32>,
}

/// A camera that cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CameraError {
    /// The field of view is not an angle in (0, 180) degrees.
    #[error("field of view {0} must be in (0, 180) degrees")]
    FieldOfView(f32),
    /// The camera's position or axes are not finite, or its axes are parallel or zero.
    #[error("degenerate camera: {0}")]
    Degenerate(String),
    /// The camera is farther from the origin than f32 ray tracing resolves.
    #[error("{0}")]
    TooFar(String),
    /// pbrt's screen window is empty or not finite.
    #[error("screen window {0:?} must be finite with x0 < x1 and y0 < y1")]
    ScreenWindow([f32; 4]),
}

impl Camera {
    /// A camera at `eye` looking at `target`, with `up` giving the image's vertical and a
    /// vertical field of view of `fov_y` degrees. Errors on degenerate input.
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3, fov_y: f32) -> Result<Self, CameraError> {
        if let Some(what) = crate::extent::extent_error(eye.abs().max_element()) {
            return Err(CameraError::TooFar(format!("camera position: {what}")));
        }
        let forward = (target - eye).normalize_or_zero();
        let right = forward.cross(up).normalize_or_zero();
        if forward == Vec3::ZERO || right == Vec3::ZERO || !eye.is_finite() {
            return Err(CameraError::Degenerate(format!(
                "eye {eye}, target {target}, up {up}"
            )));
        }
        Self::from_basis(
            eye,
            forward,
            right,
            right.cross(forward),
            FieldOfView::Vertical(fov_y),
            None,
        )
    }

    /// A camera whose film spans `right` (image x) and `up` (image y) around `forward`: a
    /// film point (sx, sy) in units of tan(fov / 2) looks along forward + sx right + sy up.
    /// The basis may be left-handed (pbrt-v4's is) and is used as given.
    pub fn from_basis(
        position: Vec3,
        forward: Vec3,
        right: Vec3,
        up: Vec3,
        fov: FieldOfView,
        screen_window: Option<[f32; 4]>,
    ) -> Result<Self, CameraError> {
        let (FieldOfView::Vertical(angle) | FieldOfView::ShorterAxis(angle)) = fov;
        if !(angle > 0.0 && angle < 180.0) {
            return Err(CameraError::FieldOfView(angle));
        }
        let finite = [position, forward, right, up].iter().all(|v| v.is_finite());
        if !finite || forward.cross(right).length() < 1e-12 || up.length() < 1e-12 {
            return Err(CameraError::Degenerate(format!(
                "position {position}, forward {forward}, right {right}, up {up}"
            )));
        }
        if let Some(what) = crate::extent::extent_error(position.abs().max_element()) {
            return Err(CameraError::TooFar(format!("camera position: {what}")));
        }
        if let Some(w) = screen_window {
            if !w.iter().all(|v| v.is_finite()) || w[0] >= w[1] || w[2] >= w[3] {
                return Err(CameraError::ScreenWindow(w));
            }
        }
        Ok(Camera {
            position,
            forward,
            right,
            up,
            fov,
            screen_window,
            filter: PixelFilter::default(),
            white_balance: None,
        })
    }

    /// What the film does to every sample's linear sRGB: its white balance, if it has one.
    pub fn sensor_response(&self) -> Option<Mat3> {
        self.white_balance.map(white_balance::srgb_white_balance)
    }

    /// Unit viewing direction.
    pub fn forward(&self) -> Vec3 {
        self.forward.normalize()
    }

    /// The film basis (forward, right, up) as given.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        (self.forward, self.right, self.up)
    }

    /// The film's extent (x0, x1, y0, y1) in the camera's tangent plane for a `width` x
    /// `height` image.
    pub fn window(&self, width: u32, height: u32) -> [f32; 4] {
        let aspect = width as f32 / height as f32;
        let (angle, base) = match self.fov {
            FieldOfView::Vertical(a) => (a, [-aspect, aspect, -1.0, 1.0]),
            FieldOfView::ShorterAxis(a) if aspect >= 1.0 => (a, [-aspect, aspect, -1.0, 1.0]),
            FieldOfView::ShorterAxis(a) => (a, [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect]),
        };
        let t = (0.5 * angle.to_radians()).tan();
        self.screen_window.unwrap_or(base).map(|v| v * t)
    }

    /// The primary ray through film position `film` (pixels, x right, y down, (0,0) the top
    /// left corner of the image) on a `width` x `height` film.
    pub fn generate_ray(&self, film: Vec2, width: u32, height: u32) -> Ray {
        let [x0, x1, y0, y1] = self.window(width, height);
        let sx = x0 + (x1 - x0) * film.x / width as f32;
        let sy = y1 - (y1 - y0) * film.y / height as f32;
        Ray::new(
            self.position,
            (self.forward + self.right * sx + self.up * sy).normalize(),
        )
    }

    /// Where `p` appears on a `width` x `height` film, or `None` when it lies behind the
    /// pinhole or outside the film: the inverse of [`Camera::generate_ray`].
    pub fn project(&self, p: Vec3, width: u32, height: u32) -> Option<Projection> {
        let v = p - self.position;
        // v = t (forward + sx right + sy up): solve for (t, t sx, t sy).
        let basis = Mat3::from_cols(self.forward, self.right, self.up);
        let c = basis.inverse() * v;
        if !(c.x > 0.0) {
            return None;
        }
        let (sx, sy) = (c.y / c.x, c.z / c.x);
        let [x0, x1, y0, y1] = self.window(width, height);
        let film = Vec2::new(
            (sx - x0) / (x1 - x0) * width as f32,
            (y1 - sy) / (y1 - y0) * height as f32,
        );
        let inside =
            film.x >= 0.0 && film.x < width as f32 && film.y >= 0.0 && film.y < height as f32;
        let distance = v.length();
        if !inside || !(distance > 0.0) {
            return None;
        }
        // The film plane's point s = forward + sx right + sy up, of area |right x up| per unit
        // of (sx, sy), subtends the solid angle |(right x up) . s| / |s|^3 per unit area.
        let s = self.forward + self.right * sx + self.up * sy;
        let pixel_area = (x1 - x0) * (y1 - y0) / (width as f32 * height as f32);
        let per_area = self.right.cross(self.up).dot(s).abs() / s.length().powi(3);
        Some(Projection {
            film,
            dir: v / distance,
            distance,
            dir_pdf: 1.0 / (per_area * pixel_area),
        })
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

    /// A camera with a skewed, unnormalised, left-handed basis and an off-centre window, as
    /// pbrt-v4's scenes may give.
    fn skewed() -> Camera {
        Camera::from_basis(
            Vec3::new(0.3, -1.0, 2.0),
            Vec3::new(0.1, 2.0, 0.2),
            Vec3::new(-1.5, 0.1, 0.0),
            Vec3::new(0.2, 0.0, 1.2),
            FieldOfView::ShorterAxis(50.0),
            Some([-1.2, 0.8, -0.5, 0.9]),
        )
        .expect("camera")
    }

    #[test]
    fn projection_inverts_generate_ray() {
        let c = skewed();
        let (w, h) = (320, 200);
        for (i, film) in [(3.5, 7.25), (160.0, 100.0), (319.0, 1.0), (0.5, 199.5)]
            .into_iter()
            .enumerate()
        {
            let film = Vec2::new(film.0, film.1);
            let ray = c.generate_ray(film, w, h);
            let p = ray.at(0.7 + 3.0 * i as f32);
            let q = c.project(p, w, h).expect("in view");
            assert!((q.film - film).length() < 2e-3, "{film} -> {}", q.film);
            assert!((q.dir - ray.d).length() < 1e-5);
            assert!((q.distance - (0.7 + 3.0 * i as f32)).abs() < 1e-4);
        }
        assert!(
            c.project(c.position - c.forward(), w, h).is_none(),
            "behind"
        );
        let off = c.generate_ray(Vec2::new(330.0, 100.0), w, h).at(2.0);
        assert!(c.project(off, w, h).is_none(), "outside the film");
    }

    #[test]
    fn the_direction_density_is_the_inverse_jacobian_of_the_film_map() {
        // A pixel's worth of film positions around `film` covers the solid angle of the
        // four directions' spherical quadrilateral: about 1 / dir_pdf.
        let c = skewed();
        let (w, h) = (64, 48);
        for film in [
            Vec2::new(10.0, 10.0),
            Vec2::new(50.0, 30.0),
            Vec2::new(32.0, 47.0),
        ] {
            let e = 1e-2;
            let d = |dx: f32, dy: f32| c.generate_ray(film + Vec2::new(dx, dy), w, h).d;
            let (a, b, cc) = (d(0.0, 0.0), d(e, 0.0), d(0.0, e));
            let solid = (b - a).cross(cc - a).length() / (e * e);
            let q = c.project(c.position + a * 5.0, w, h).expect("in view");
            assert!(
                (q.dir_pdf * solid - 1.0).abs() < 1e-2,
                "{film}: {} against {}",
                q.dir_pdf,
                1.0 / solid
            );
        }
    }
}
