//! What learned light samplers learn from: the render's own light samples. During a pass each
//! 8x8 block keeps the light samples of its paths that found light; after the pass the
//! sampler sees every block's records in block order, so what it learns, and the next pass's
//! pixels, do not depend on the number of threads.

use crate::sample_context::SampleContext;
use fenestra_core::Vec3;

/// Records kept per pass at most (44 bytes each): a pass of many samples keeps the records
/// of a random share of its paths.
pub const RECORD_BUDGET: u64 = 1 << 21;

/// One light sample that found light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightRecord {
    /// The shading point.
    pub p: Vec3,
    /// Its shading normal.
    pub n: Vec3,
    /// The light picked.
    pub light: u32,
    /// The unit direction sampled towards it.
    pub wi: Vec3,
    /// Luminance of what the sample brought (BSDF, cosine, visibility; no MIS weight) over
    /// its density, divided by the probability of picking the light: its mean over a
    /// region's samples estimates the light's share of the region's direct light.
    pub weight: f32,
}

/// The light records of one block in one pass.
#[derive(Clone, Debug, Default)]
pub struct LightRecords {
    /// Share of path samples whose records are kept (0: none).
    rate: f32,
    /// Whether the current path sample's records are kept.
    on: bool,
    /// The records, in sample order.
    pub records: Vec<LightRecord>,
}

impl LightRecords {
    /// Records that keep nothing (no learning sampler, or a pass it does not learn from).
    pub fn off() -> Self {
        Self::default()
    }

    /// Records that keep the light samples of a share `rate` of path samples.
    pub fn new(rate: f32) -> Self {
        LightRecords {
            rate,
            ..Self::default()
        }
    }

    /// The share of path samples to keep so that `samples` path samples with about
    /// `per_sample` records each stay within [`RECORD_BUDGET`].
    pub fn rate_for(samples: u64, per_sample: f64) -> f32 {
        let expected = samples as f64 * per_sample.max(1e-3);
        (RECORD_BUDGET as f64 / expected).min(1.0) as f32
    }

    /// Starts the path sample `ctx`: whether its records are kept is decided by a hash of
    /// its pixel and index, so the same samples are kept whatever the thread count.
    pub fn start_sample(&mut self, ctx: &SampleContext) {
        self.on =
            self.rate >= 1.0 || (self.rate > 0.0 && unit_hash(ctx.pixel(), ctx.index) < self.rate);
    }

    /// Whether records of the current sample are kept.
    pub fn on(&self) -> bool {
        self.on
    }

    /// The records that `keep` keeps, in their order.
    pub fn retained(&self, keep: impl Fn(&LightRecord) -> bool) -> LightRecords {
        LightRecords {
            rate: self.rate,
            on: self.on,
            records: self.records.iter().copied().filter(|r| keep(r)).collect(),
        }
    }

    /// Keeps `record` (callers ask [`LightRecords::on`] when they build it, which may be
    /// before its shadow ray is tested and other samples have started).
    pub fn push(&mut self, record: LightRecord) {
        self.records.push(record);
    }
}

/// A number in [0, 1) from a pixel and a sample index (SplitMix64's finaliser).
fn unit_hash(pixel: u64, index: u32) -> f32 {
    let mut z = pixel
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(u64::from(index).wrapping_mul(0xD1B5_4A32_D192_ED03));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 40) as f32 / (1u64 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_kept_share_of_samples_is_the_rate() {
        let mut records = LightRecords::new(0.25);
        let mut kept = 0;
        let n = 40_000;
        for i in 0..n {
            let ctx = SampleContext {
                x: i % 200,
                y: i / 200,
                width: 200,
                height: 200,
                block: 0,
                pass: 0,
                index: i % 7,
            };
            records.start_sample(&ctx);
            kept += usize::from(records.on());
        }
        // Binomial(40000, 0.25): standard deviation 87.
        assert!((kept as f64 - 10_000.0).abs() < 450.0, "kept {kept} of {n}");
        assert_eq!(LightRecords::rate_for(1 << 20, 1.0), 1.0);
        assert_eq!(LightRecords::rate_for(1 << 23, 1.0), 0.25);
    }
}
