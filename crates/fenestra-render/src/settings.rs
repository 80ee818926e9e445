//! How much to render: samples, time, seed.

/// What a render is asked for, whatever the integrator.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    /// Samples per pixel (an upper bound when `time_limit` is set; adaptive integrators
    /// read it as their budget).
    pub spp: u32,
    /// Stop after about this many seconds of rendering, at a pass boundary. Preparation
    /// (portal estimation, caches) comes on top: equal-time comparisons give every technique
    /// the same sampling time and charge the preparation in the statistics' total time.
    pub time_limit: Option<f64>,
    /// Seed of every sample stream: sample `i` of pixel `p` uses the stream (seed, p, i).
    pub seed: u64,
}
