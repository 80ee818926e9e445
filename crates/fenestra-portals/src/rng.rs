//! A small deterministic generator (counter hashed with the seed): results do not depend on
//! threads or on a global state.

use fenestra_core::sampler::{hash_combine, hash_u32};

pub struct Rng {
    seed: u32,
    counter: u32,
}

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng {
            seed: hash_combine(seed as u32, (seed >> 32) as u32),
            counter: 0,
        }
    }

    /// Uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        self.counter = self.counter.wrapping_add(1);
        let hi = hash_u32(hash_combine(self.seed, self.counter)) as u64;
        let lo = hash_u32(hash_combine(self.seed ^ 0x5bd1_e995, self.counter)) as u64;
        ((hi << 21) ^ lo) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in 0..n (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next_f64() * n as f64) as usize).min(n - 1)
    }
}
