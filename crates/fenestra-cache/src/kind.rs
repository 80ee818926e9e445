//! What each kind of cache record does (SDRC's L-trees in `glossy`, SH radiance in
//! `harmonics`, irradiance in `irradiance`): how a record is made at a point from its rays,
//! and how the records near a point give its light. `gather` picks the kind a point needs.

use crate::record::{Payload, Record};
use crate::record_rays::RecordRays;
use crate::spatial::{Delta, SpatialCache};
use fenestra_core::stats::RayCounters;
use fenestra_core::Rgb;
use fenestra_render::integrator::Shading;
use fenestra_render::RenderScene;

/// One kind of cache record.
pub(crate) trait CacheKind {
    /// What its records hold.
    type Payload: Payload;

    /// A new record at `s` (its frame about the shading normal on the viewer's side) under
    /// maximum interpolation error `a`, from rays traced with `tracing`; `delta` counts the
    /// rays.
    fn create(
        &self,
        tracing: &mut RecordRays,
        delta: &mut Delta<Self::Payload>,
        scene: &RenderScene,
        s: &Shading,
        a: f32,
        rays: &mut RayCounters,
    ) -> Record<Self::Payload>;

    /// What the records near `s` (those `delta.near` holds) give there: the light the point
    /// reflects towards its viewer (glossy kinds), or its irradiance (the irradiance cache).
    /// A kind that adds samples to its records (SDRC's lazy updates) adds them to `delta`.
    fn interpolate(
        &self,
        tracing: &mut RecordRays,
        cache: &SpatialCache<Self::Payload>,
        delta: &mut Delta<Self::Payload>,
        scene: &RenderScene,
        s: &Shading,
        rays: &mut RayCounters,
    ) -> Rgb;
}
