//! Deterministic sample streams: a sample's numbers depend only on (seed, pixel, sample index,
//! dimension), never on the thread that draws them.

use glam::Vec2;

/// Owen-scrambled Sobol points (Burley 2020), padded: dimensions are taken four at a time
/// from the 4D Sobol set, each group with its own scrambling seed, which keeps 4D
/// stratification without relying on the quality of high Sobol dimensions.
#[derive(Clone, Debug)]
pub struct Sampler {
    pixel_seed: u32,
    index: u32,
    dim: u32,
    /// The current 4D group's values (one `sample_4d` call fills all four).
    group: [f32; 4],
    group_index: u32,
}

/// A 32-bit integer hash (Wellons' lowbias32).
pub fn hash_u32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// Hashes two 32-bit values into one (for seeding streams).
pub fn hash_combine(a: u32, b: u32) -> u32 {
    hash_u32(
        a ^ hash_u32(b)
            .wrapping_add(0x9e37_79b9)
            .wrapping_add(a << 6)
            .wrapping_add(a >> 2),
    )
}

/// Number of samples one Sobol scramble covers; beyond it the stream is re-seeded.
const SOBOL_LENGTH: u32 = 1 << 16;

impl Sampler {
    /// The stream for sample `index` of the pixel (or other item) `pixel` under `seed`.
    pub fn new(seed: u64, pixel: u64, index: u32) -> Self {
        let s = hash_combine(seed as u32, (seed >> 32) as u32);
        let p = hash_combine(pixel as u32, (pixel >> 32) as u32);
        Sampler {
            pixel_seed: hash_combine(s, p),
            index,
            dim: 0,
            group: [0.0; 4],
            group_index: u32::MAX,
        }
    }

    /// The stream's next number in [0, 1).
    pub fn next_1d(&mut self) -> f32 {
        let d = self.dim;
        self.dim += 1;
        if d / 4 != self.group_index {
            self.group_index = d / 4;
            let block = self.index / SOBOL_LENGTH;
            let seed = hash_combine(hash_combine(self.pixel_seed, d / 4), block);
            self.group = sobol_burley::sample_4d(self.index % SOBOL_LENGTH, 0, seed);
        }
        self.group[(d % 4) as usize]
    }

    /// The stream's next two numbers, from the same 4D Sobol group.
    pub fn next_2d(&mut self) -> Vec2 {
        // Keep both coordinates of a 2D sample in the same 4D group.
        if self.dim % 4 == 3 {
            self.dim += 1;
        }
        Vec2::new(self.next_1d(), self.next_1d())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let draw = |seed, pixel, idx| {
            let mut s = Sampler::new(seed, pixel, idx);
            (0..10).map(|_| s.next_1d()).collect::<Vec<_>>()
        };
        assert_eq!(draw(1, 5, 3), draw(1, 5, 3));
        assert_ne!(draw(1, 5, 3), draw(1, 6, 3));
        assert_ne!(draw(1, 5, 3), draw(2, 5, 3));
        assert_ne!(draw(1, 5, 3), draw(1, 5, 4));
        assert_ne!(draw(1, 5, 3), draw(1, 5, 3 + SOBOL_LENGTH));
    }

    #[test]
    fn one_dimension_is_stratified() {
        // The first 256 samples of any Owen-scrambled Sobol dimension fall one per stratum.
        for dim in 0..9 {
            let mut strata = [0u32; 256];
            for i in 0..256 {
                let mut s = Sampler::new(7, 42, i);
                let mut x = 0.0;
                for _ in 0..=dim {
                    x = s.next_1d();
                }
                strata[(x * 256.0) as usize] += 1;
            }
            assert!(strata.iter().all(|&c| c == 1), "dimension {dim}");
        }
    }
}
