//! What a render did, as one typed record: the renderer writes it as the JSON sidecar beside
//! every image, and the measurement tools read it back (nothing reads the sidecar by string
//! keys). Integrators add their own figures (passes, cache records, portals, ...) to
//! [`RenderStats::extra`].

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::ops::AddAssign;

/// Rays traced and samples dropped, counted per worker and summed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct RayCounters {
    /// Primary rays from the camera (closest hit).
    pub camera: u64,
    /// Secondary closest-hit rays (path continuation).
    pub bounce: u64,
    /// Visibility rays of next-event estimation (shadow, light and portal rays).
    pub shadow: u64,
    /// Samples that were NaN, infinite or beyond the film's range (2^31) and never reached
    /// the film.
    pub dropped: u64,
}

impl RayCounters {
    /// Camera, bounce and shadow rays together.
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

/// The error of a render against a reference after one pass (a point of the convergence
/// curve).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConvergencePoint {
    /// Samples every pixel had.
    pub spp: u32,
    /// Seconds since the render started (preparation included).
    pub time_s: f64,
    /// Mean squared error against the reference.
    pub mse: f64,
    /// Relative mean squared error against the reference.
    pub rel_mse: f64,
    /// The share of the image's light that light paths brought, for renders that trace
    /// them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub light_path_share: Option<f64>,
    /// The share of the image's variance that the light paths' estimates hold.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub light_path_variance_share: Option<f64>,
}

/// Everything a render reports: what was rendered, how long it took, what it traced.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct RenderStats {
    /// The scene's name.
    pub scene: String,
    /// A hash of the scene's content (its files' bytes; a built-in scene's name and
    /// fenestra's version), which tells apart scenes of one name; empty where unknown.
    pub scene_content: String,
    /// The integrator's name (`hf`, `af_hf`, ...).
    pub integrator: String,
    /// Every integrator setting that changes the picture.
    pub settings: serde_json::Value,
    /// The ray-query backend.
    pub backend: String,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel every pixel received (fewer than asked if interrupted).
    pub spp: u32,
    /// Largest per-pixel sample count (above `spp` after an interruption or with adaptive
    /// sampling).
    pub spp_max: u32,
    /// Maximum path length in segments, for integrators that trace paths.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_depth: Option<u32>,
    /// Seed of the sample streams.
    pub seed: u64,
    /// Worker threads.
    pub threads: usize,
    /// Seconds in all: preparation and rendering.
    pub time_s: f64,
    /// Seconds of preparation (pre-passes, caches, portal estimation) within `time_s`.
    pub prepare_s: f64,
    /// Passes over the image.
    pub passes: u32,
    /// Rays of each kind.
    pub rays: RayCounters,
    /// All rays traced.
    pub total_rays: u64,
    /// Millions of rays per second of rendering (`time_s` less `prepare_s`).
    pub mrays_per_s: f64,
    /// Shadow rays per pixel.
    pub shadow_rays_per_pixel: f64,
    /// Stopped by the user: the image holds the samples taken so far.
    pub interrupted: bool,
    /// Figures an integrator adds (for example `portals`, `cache_records`), by name.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub extra: BTreeMap<String, f64>,
    /// Error against a reference after each pass, when one was given.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub convergence: Vec<ConvergencePoint>,
    /// The key under which a reference render is cached.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference_key: Option<String>,
    /// What denoised the image written beside it (OUT.denoised.exr), if anything did: the
    /// denoiser, its version, device and settings.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub denoiser: Option<serde_json::Value>,
}

impl RenderStats {
    /// Fills the figures derived from the others (total rays, rates, rays per pixel).
    pub fn derive_rates(&mut self) {
        let pixels = (self.width as u64 * self.height as u64).max(1);
        self.total_rays = self.rays.total_rays();
        let rendering = (self.time_s - self.prepare_s).max(1e-9);
        self.mrays_per_s = self.total_rays as f64 / rendering / 1e6;
        self.shadow_rays_per_pixel = self.rays.shadow as f64 / pixels as f64;
    }

    /// The one-line summary the command line prints.
    pub fn summary(&self) -> String {
        let spp = if self.spp == self.spp_max {
            self.spp.to_string()
        } else {
            format!("{}-{}", self.spp, self.spp_max)
        };
        let prepare = if self.prepare_s >= 0.005 {
            format!(" ({:.2} s preparing)", self.prepare_s)
        } else {
            String::new()
        };
        format!(
            "{} {} {}x{}: {:.2} s{prepare}, {} spp, {:.2} Mrays/s ({} camera, {} bounce, {} shadow), {} samples dropped{}",
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_round_trip_through_json_and_old_sidecars_still_read() {
        let mut s = RenderStats {
            scene: "box".into(),
            integrator: "af_hf".into(),
            width: 4,
            height: 2,
            time_s: 2.0,
            rays: RayCounters {
                camera: 8,
                bounce: 4,
                shadow: 16,
                dropped: 1,
            },
            ..Default::default()
        };
        s.extra.insert("portals".into(), 4.0);
        s.derive_rates();
        assert_eq!(s.total_rays, 28);
        assert_eq!(s.shadow_rays_per_pixel, 2.0);
        let text = serde_json::to_string(&s).expect("json");
        let back: RenderStats = serde_json::from_str(&text).expect("read");
        assert_eq!(back, s);
        // A sidecar written before `prepare_s`, `passes` and `extra` existed.
        let old: RenderStats =
            serde_json::from_str(r#"{"scene":"box","time_s":1.5,"max_depth":6,"spp":4}"#)
                .expect("old sidecar");
        assert_eq!((old.time_s, old.max_depth, old.spp), (1.5, Some(6), 4));
    }
}
