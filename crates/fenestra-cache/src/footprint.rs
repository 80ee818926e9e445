//! The size of the camera's pixels in the scene, and the bounds it sets on a record's
//! validity radius R_i (in pixels, so that records resolve what the image can show).

use crate::options::MAX_REACH_PX;
use fenestra_core::Vec2;
use fenestra_render::RenderScene;

/// The image size, in pixels along its larger side, at which the reach bounds are in pixels;
/// larger images of the same view scale them with their size, so that the caches resolve the
/// same detail of the scene, at about the same cost, at any resolution.
const REACH_SIDE: u32 = 256;

/// The size of the camera's pixels in the scene.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PixelFootprint {
    /// Angle between neighbouring pixels' camera rays.
    angle: f32,
    /// Distance between their origins (orthographic cameras).
    spacing: f32,
    /// The image's larger side over [`REACH_SIDE`], at least 1: what the reach bounds'
    /// pixels are scaled by.
    reach_scale: f32,
}

impl PixelFootprint {
    /// The footprint of a `width` x `height` image's pixels, measured from two neighbouring
    /// pixels' camera rays at its centre.
    pub(crate) fn measure(scene: &RenderScene, width: u32, height: u32) -> Self {
        let camera = &scene.scene.camera;
        let c = Vec2::new(width as f32 * 0.5, height as f32 * 0.5);
        let (a, b) = (
            camera.generate_ray(c, width, height),
            camera.generate_ray(c + Vec2::X, width, height),
        );
        PixelFootprint {
            angle: a.d.dot(b.d).clamp(-1.0, 1.0).acos(),
            spacing: (a.o - b.o).length(),
            reach_scale: (width.max(height) as f32 / REACH_SIDE as f32).max(1.0),
        }
    }

    /// A pixel's size at distance `t` from the camera.
    pub(crate) fn at(&self, t: f32) -> f32 {
        self.spacing + t * self.angle
    }

    /// Bounds of R_i for a record at distance `t` from the camera under maximum error `a`:
    /// `min_reach` and [`MAX_REACH_PX`] pixels there (scaled as the image is).
    pub(crate) fn radius_bounds(&self, t: f32, a: f32, min_reach: f32) -> (f32, f32) {
        let reach = self.at(t) * self.reach_scale / a;
        (min_reach * reach, MAX_REACH_PX * reach)
    }
}
