//! How much to render: samples, time, seed.

/// What a render is asked for, whatever the integrator.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    /// Samples per pixel (an upper bound when `time_limit` is set; adaptive integrators
    /// read it as their budget).
    pub spp: u32,
    /// Index of every pixel's first sample: a render of `spp` samples from `first_sample`
    /// is one piece of a render split by sample ranges (scale-out), and merges exactly with
    /// the other pieces. 0 for a whole render.
    pub first_sample: u32,
    /// Stop after about this many seconds, at a pass boundary, preparation (portal
    /// estimation, pilots, caches) included: equal-time comparisons give every technique the
    /// same wall time. The first pass always runs, so a preparation that took it all still
    /// leaves an image.
    pub time_limit: Option<f64>,
    /// Seed of every sample stream: sample `i` of pixel `p` uses the stream (seed, p, i).
    pub seed: u64,
}
