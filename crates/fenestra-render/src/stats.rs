//! What a render did: time, samples, rays of each kind, dropped samples.

use serde::Serialize;
use std::ops::AddAssign;

/// Rays traced and samples dropped, counted per worker and summed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct RayCounters {
    /// Primary rays from the camera (closest hit).
    pub camera: u64,
    /// Secondary closest-hit rays (path continuation).
    pub bounce: u64,
    /// Any-hit visibility rays (next-event estimation).
    pub shadow: u64,
    /// Path samples that were NaN or infinite and never reached the film.
    pub dropped: u64,
}

impl RayCounters {
    pub fn total_rays(&self) -> u64 {
        self.camera + self.bounce + self.shadow
    }
}

impl AddAssign for RayCounters {
    fn add_assign(&mut self, o: RayCounters) {
        self.camera += o.camera;
        self.bounce += o.bounce;
        self.shadow += o.shadow;
        self.dropped += o.dropped;
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct RenderStats {
    pub scene: String,
    pub integrator: String,
    pub backend: String,
    pub width: u32,
    pub height: u32,
    /// Samples per pixel every pixel received (fewer than asked if interrupted).
    pub spp: u32,
    /// Largest per-pixel sample count (differs from `spp` only after an interruption).
    pub spp_max: u32,
    pub max_depth: u32,
    pub seed: u64,
    pub threads: usize,
    pub time_s: f64,
    pub rays: RayCounters,
    pub total_rays: u64,
    pub mrays_per_s: f64,
    pub shadow_rays_per_pixel: f64,
    pub interrupted: bool,
}

impl RenderStats {
    /// The one-line summary the CLI prints.
    pub fn summary(&self) -> String {
        let spp = if self.spp == self.spp_max {
            self.spp.to_string()
        } else {
            format!("{}-{}", self.spp, self.spp_max)
        };
        format!(
            "{} {} {}x{}: {:.2} s, {} spp, {:.2} Mrays/s ({} camera, {} bounce, {} shadow), {} samples dropped{}",
            self.scene,
            self.integrator,
            self.width,
            self.height,
            self.time_s,
            spp,
            self.mrays_per_s,
            self.rays.camera,
            self.rays.bounce,
            self.rays.shadow,
            self.rays.dropped,
            if self.interrupted { " (interrupted: partial result)" } else { "" }
        )
    }
}
