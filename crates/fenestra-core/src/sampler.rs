//! Deterministic sample streams: a sample's numbers depend only on (seed, pixel, sample index,
//! dimension), never on the thread that draws them.

use glam::{Vec2, Vec3};
use sobol_burley::parts;
use std::sync::LazyLock;

/// Owen-scrambled Sobol points (Burley 2020), padded: dimensions are taken four at a time
/// from the 4D Sobol set, each group with its own scrambling seed, which keeps 4D
/// stratification without relying on the quality of high Sobol dimensions.
#[derive(Clone, Debug)]
pub struct Sampler {
    pixel_seed: u32,
    /// `hash_u32` of the index's block of [`SOBOL_LENGTH`] samples.
    block_hash: u32,
    index: u32,
    dim: u32,
    /// The values of the current pair of 4D groups (computed together, eight lanes wide).
    pair: [f32; 8],
    pair_index: u32,
}

/// A 32-bit integer hash (Wellons' lowbias32).
pub const fn hash_u32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// Hashes two 32-bit values into one (for seeding streams).
pub fn hash_combine(a: u32, b: u32) -> u32 {
    combine_hashed(a, hash_u32(b))
}

/// [`hash_combine`]`(a, b)` from `a` and `hash_u32(b)`.
const fn combine_hashed(a: u32, hashed_b: u32) -> u32 {
    hash_u32(
        a ^ hashed_b
            .wrapping_add(0x9e37_79b9)
            .wrapping_add(a << 6)
            .wrapping_add(a >> 2),
    )
}

/// `hash_u32` of the first 4D groups' indices, so that a group's seed takes two hashes
/// rather than four.
static GROUP_HASHES: [u32; 64] = {
    let mut t = [0; 64];
    let mut g = 0;
    while g < 64 {
        t[g] = hash_u32(g as u32);
        g += 1;
    }
    t
};

/// Number of samples one Sobol scramble covers; beyond it the stream is re-seeded.
const SOBOL_LENGTH: u32 = 1 << 16;

impl Sampler {
    /// The stream for sample `index` of the pixel (or other item) `pixel` under `seed`.
    pub fn new(seed: u64, pixel: u64, index: u32) -> Self {
        let s = hash_combine(seed as u32, (seed >> 32) as u32);
        let p = hash_combine(pixel as u32, (pixel >> 32) as u32);
        Sampler {
            pixel_seed: hash_combine(s, p),
            block_hash: hash_u32(index / SOBOL_LENGTH),
            index,
            dim: 0,
            pair: [0.0; 8],
            pair_index: u32::MAX,
        }
    }

    /// The stream for sample `index` of `pixel` in stream `stream` of `seed`: streams draw
    /// independently scrambled points, each from its own index 0 (stream 0 is
    /// [`Sampler::new`]'s). The points of one stream are stratified against each other, so
    /// an estimator that samples by what it learned from earlier samples must draw the
    /// samples that use it from another stream than the samples it learned from: within
    /// one stream they would not be independent of what was learned, and the estimate
    /// would be biased.
    pub fn in_stream(seed: u64, stream: u32, pixel: u64, index: u32) -> Self {
        let mut sampler = Self::new(seed, pixel, index);
        if stream != 0 {
            sampler.pixel_seed = hash_combine(sampler.pixel_seed, stream);
        }
        sampler
    }

    /// The scrambling seed of 4D group `group`: hash_combine(hash_combine(pixel seed,
    /// group), block).
    fn group_seed(&self, group: u32) -> u32 {
        let group_hash = match GROUP_HASHES.get(group as usize) {
            Some(&h) => h,
            None => hash_u32(group),
        };
        combine_hashed(combine_hashed(self.pixel_seed, group_hash), self.block_hash)
    }

    /// The stream's next number in [0, 1).
    pub fn next_1d(&mut self) -> f32 {
        let d = self.dim;
        self.dim += 1;
        if d / 8 != self.pair_index {
            self.pair_index = d / 8;
            let seeds = [self.group_seed(d / 8 * 2), self.group_seed(d / 8 * 2 + 1)];
            self.pair = sobol_4d_pair(self.index % SOBOL_LENGTH, seeds);
        }
        self.pair[(d % 8) as usize]
    }

    /// The stream's next two numbers, from the same 4D Sobol group.
    pub fn next_2d(&mut self) -> Vec2 {
        // Keep both coordinates of a 2D sample in the same 4D group.
        if self.dim % 4 == 3 {
            self.dim += 1;
        }
        Vec2::new(self.next_1d(), self.next_1d())
    }

    /// The stream's next three numbers, from the same 4D Sobol group, so that they are
    /// stratified together: a choice among parts (a light among the triangles of an
    /// emitter) and a 2D point on the part chosen cover the whole as one 2D sample would.
    pub fn next_3d(&mut self) -> Vec3 {
        if self.dim % 4 >= 2 {
            self.dim = self.dim.next_multiple_of(4);
        }
        Vec3::new(self.next_1d(), self.next_1d(), self.next_1d())
    }
}

/// The unscrambled 4D Sobol points (bit-reversed, as sobol_burley keeps them) of the
/// reversed indices `b << 24` (first 256) and `b << 16` (last 256).
static SOBOL_BYTES: LazyLock<[[u32; 4]; 512]> = LazyLock::new(|| {
    let mut t = [[0; 4]; 512];
    for b in 0..256u32 {
        t[b as usize] = parts::sobol_int4_rev(b << 24, 0).into();
        t[256 + b as usize] = parts::sobol_int4_rev(b << 16, 0).into();
    }
    t
});

/// `sobol_burley::sample_4d(index, 0, seed)` for the two seeds `seeds`, bit for bit: the
/// crate's steps on eight lanes at once, with the Sobol matrix product replaced by two
/// table lookups (the product is linear over GF(2), so the point of a 16-bit index is the
/// XOR of the points of its two bytes). A path takes its dimensions two groups at a time,
/// and eight lanes cost about what four do; where the CPU has AVX2 (checked at run time),
/// the same code runs on it (integer arithmetic: the same bits either way).
fn sobol_4d_pair(index: u32, seeds: [u32; 2]) -> [f32; 8] {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2.
        return unsafe { sobol_4d_pair_avx2(index, seeds) };
    }
    sobol_4d_lanes(index, seeds)
}

/// [`sobol_4d_lanes`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn sobol_4d_pair_avx2(index: u32, seeds: [u32; 2]) -> [f32; 8] {
    sobol_4d_lanes(index, seeds)
}

/// The work of [`sobol_4d_pair`], written lane by lane for the compiler to vectorise.
#[inline(always)]
fn sobol_4d_lanes(index: u32, seeds: [u32; 2]) -> [f32; 8] {
    debug_assert!(index < SOBOL_LENGTH);
    const DIMENSION_SALT: [u32; 4] = [0x912f_69ba, 0x174f_18ab, 0x691e_72ca, 0xb40c_c1b8];
    let t = &*SOBOL_BYTES;
    let mut points = [0u32; 8];
    let mut scrambles = [0u32; 8];
    for (g, &seed) in seeds.iter().enumerate() {
        // Burley's index shuffle: a nested uniform scramble of the reversed index.
        let shuffled_rev =
            parts::owen_scramble_rev(index.reverse_bits(), parts::hash(seed ^ 0x79c6_8e4a));
        let high = t[(shuffled_rev >> 24) as usize];
        let low = t[256 + ((shuffled_rev >> 16) & 0xff) as usize];
        let s = seed.wrapping_mul(0x9c8f_2d3b);
        for k in 0..4 {
            points[4 * g + k] = high[k] ^ low[k];
            scrambles[4 * g + k] = s ^ DIMENSION_SALT[k];
        }
    }
    let mut out = [0.0; 8];
    for i in 0..8 {
        let scrambled = parts::owen_scramble_rev(points[i], parts::hash(scrambles[i]));
        out[i] = parts::u32_to_f32_norm(scrambled.reverse_bits());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paired_table_sobol_equals_the_crates() {
        for seed in [0, 1, 0xdead_beef, 12345] {
            for index in (0..SOBOL_LENGTH).step_by(7) {
                let seeds = [hash_u32(seed ^ index), hash_u32(seed ^ index ^ 0x5555)];
                let crates = [0, 1].map(|g| sobol_burley::sample_4d(index, 0, seeds[g]));
                let expected: Vec<f32> = crates.concat();
                // Both builds: the one this machine dispatches to, and the portable one.
                assert_eq!(
                    sobol_4d_pair(index, seeds).to_vec(),
                    expected,
                    "{index} {seeds:?}"
                );
                assert_eq!(
                    sobol_4d_lanes(index, seeds).to_vec(),
                    expected,
                    "{index} {seeds:?}"
                );
            }
        }
    }

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
        let stream = |stream, idx| {
            let mut s = Sampler::in_stream(1, stream, 5, idx);
            (0..10).map(|_| s.next_1d()).collect::<Vec<_>>()
        };
        assert_eq!(stream(0, 3), draw(1, 5, 3), "stream 0 is the plain stream");
        assert_ne!(stream(1, 3), draw(1, 5, 3));
        assert_ne!(stream(1, 3), stream(2, 3));
    }

    #[test]
    fn streams_are_not_stratified_against_each_other() {
        // Within a stream, samples 0 and 1 of a pixel fall in different halves of every
        // dimension; across streams they fall in the same half about half the time.
        let first = |stream, index, pixel| Sampler::in_stream(3, stream, pixel, index).next_1d();
        let same_half = |a: f32, b: f32| (a < 0.5) == (b < 0.5);
        let pixels = 0..2000u64;
        assert!(pixels
            .clone()
            .all(|p| !same_half(first(0, 0, p), first(0, 1, p))));
        let across = pixels
            .filter(|&p| same_half(first(1, 0, p), first(2, 0, p)))
            .count();
        assert!((900..1100).contains(&across), "{across} of 2000");
    }

    #[test]
    fn three_numbers_are_stratified_together() {
        // Whatever dimension a stream stands at, the next three numbers of its first 64
        // samples fall one per cell of a 4 x 4 x 4 grid (three numbers from two 4D groups
        // would not: their groups are scrambled independently).
        for skip in 0..6 {
            let mut cells = [0u32; 64];
            for i in 0..64 {
                let mut s = Sampler::new(11, 5, i);
                for _ in 0..skip {
                    s.next_1d();
                }
                let v = s.next_3d();
                let c = |x: f32| (x * 4.0) as usize;
                cells[c(v.x) * 16 + c(v.y) * 4 + c(v.z)] += 1;
            }
            assert!(cells.iter().all(|&n| n == 1), "after {skip}: {cells:?}");
        }
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
