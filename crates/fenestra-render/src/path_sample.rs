//! What the path loop, next-event strategies and light sampling hand each other about the
//! sample under way: which sample it is, the random stream it draws from, and where its
//! light samples (for learning light samplers) and its rays are counted; and the same for a
//! wave of samples traced together.

use crate::features::Feature;
use crate::light::LightRecords;
use crate::render_scene::RenderScene;
use crate::sample_context::SampleContext;
use fenestra_core::stats::RayCounters;
use fenestra_core::{Ray, Sampler};

/// One path sample under way.
pub struct PathSample<'a> {
    /// Which sample it is.
    pub ctx: &'a SampleContext,
    /// Its random stream.
    pub sampler: &'a mut Sampler,
    /// The light samples learning samplers learn from (its block's).
    pub records: &'a mut LightRecords,
    /// The rays traced (its block's).
    pub rays: &'a mut RayCounters,
}

/// Path samples traced together: sample `ctxs[i]` starts along `cameras[i]` and draws from
/// `samplers[i]`; their light samples and rays are counted together.
pub struct Wave<'a> {
    /// Each sample's camera ray.
    pub cameras: &'a [Ray],
    /// Which samples they are.
    pub ctxs: &'a [SampleContext],
    /// Their random streams.
    pub samplers: &'a mut [Sampler],
    /// The light samples learning samplers learn from.
    pub records: &'a mut LightRecords,
    /// The rays traced.
    pub rays: &'a mut RayCounters,
    /// Where an estimator that reads denoising features off its paths puts each sample's
    /// (empty: none asked for; left `None`: the driver takes a feature sample of its own).
    pub features: &'a mut [Option<Feature>],
}

impl Wave<'_> {
    /// The samples `ctxs` as a wave along their camera rays (each drawn from its stream in
    /// `samplers`), handed to `f`; light samples and rays are counted in `records` and `rays`,
    /// denoising features read off the paths go to `features` (empty if none are asked for).
    pub fn of_cameras<R>(
        scene: &RenderScene,
        ctxs: &[SampleContext],
        samplers: &mut [Sampler],
        records: &mut LightRecords,
        rays: &mut RayCounters,
        features: &mut [Option<Feature>],
        f: impl FnOnce(&mut Wave) -> R,
    ) -> R {
        let cameras = SampleContext::camera_rays(ctxs, &scene.scene.camera, samplers, rays);
        f(&mut Wave {
            cameras: &cameras,
            ctxs,
            samplers,
            records,
            rays,
            features,
        })
    }

    /// Sample `i` as a path sample of its own.
    pub fn sample(&mut self, i: usize) -> PathSample<'_> {
        PathSample {
            ctx: &self.ctxs[i],
            sampler: &mut self.samplers[i],
            records: &mut *self.records,
            rays: &mut *self.rays,
        }
    }
}
