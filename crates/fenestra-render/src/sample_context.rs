//! Which sample is being taken: what the drivers tell estimators, light samplers and
//! caches about a sample, and the camera ray it starts with.

use fenestra_core::stats::RayCounters;
use fenestra_core::{Ray, Sampler, Vec2};
use fenestra_scene::Camera;

/// Which sample is being taken: its pixel, the pixel's 8x8 block, the pass and the sample's
/// index within the pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampleContext {
    /// Pixel column.
    pub x: u32,
    /// Pixel row (0 at the top).
    pub y: u32,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Index of the pixel's block, row-major over the film's blocks (the image's, unless the
    /// render is cropped).
    pub block: u32,
    /// The pass, from 0.
    pub pass: u32,
    /// The sample's index within its pixel.
    pub index: u32,
}

impl SampleContext {
    /// A sample outside any film (the one pixel of a 1x1 image, pass 0), for light samplers
    /// asked at single points: tests, measurements before rendering.
    pub const SINGLE: SampleContext = SampleContext {
        x: 0,
        y: 0,
        width: 1,
        height: 1,
        block: 0,
        pass: 0,
        index: 0,
    };

    /// Row-major index of the pixel.
    pub fn pixel(&self) -> u64 {
        self.y as u64 * self.width as u64 + self.x as u64
    }

    /// The camera ray through a point drawn from the camera's pixel filter around the pixel
    /// (a uniform point of the pixel by default); the film position takes the sample's first
    /// two dimensions.
    pub fn camera_ray(
        &self,
        camera: &Camera,
        sampler: &mut Sampler,
        rays: &mut RayCounters,
    ) -> Ray {
        let film_pos =
            Vec2::new(self.x as f32, self.y as f32) + camera.filter.sample(sampler.next_2d());
        rays.camera += 1;
        camera.generate_ray(film_pos, self.width, self.height)
    }

    /// The camera rays of the samples `ctxs`, each drawn from its stream in `samplers` (a
    /// wave's first rays).
    pub fn camera_rays(
        ctxs: &[SampleContext],
        camera: &Camera,
        samplers: &mut [Sampler],
        rays: &mut RayCounters,
    ) -> Vec<Ray> {
        ctxs.iter()
            .zip(samplers.iter_mut())
            .map(|(ctx, sampler)| ctx.camera_ray(camera, sampler, rays))
            .collect()
    }
}
