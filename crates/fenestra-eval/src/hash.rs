//! A stable 64-bit content hash (FNV-1a) that can digest `Debug` output as a stream, so a
//! scene of millions of triangles is keyed without building one huge string.

/// FNV-1a over bytes.
#[derive(Clone, Copy, Debug)]
pub struct Fnv64(u64);

impl Default for Fnv64 {
    fn default() -> Self {
        Fnv64(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv64 {
    /// Digests `bytes`.
    pub fn update(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    /// The hash so far.
    pub fn finish(&self) -> u64 {
        self.0
    }
}

impl std::fmt::Write for Fnv64 {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.update(s.as_bytes());
        Ok(())
    }
}

/// Hash of a value's `Debug` form.
pub fn debug_hash(value: &impl std::fmt::Debug) -> u64 {
    let mut h = Fnv64::default();
    let _ = std::fmt::write(&mut h, format_args!("{value:?}"));
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_vectors_and_streaming() {
        let mut h = Fnv64::default();
        h.update(b"a");
        assert_eq!(h.finish(), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(debug_hash(&"x"), debug_hash(&"x"));
        assert_ne!(debug_hash(&[1.0f32, 2.0]), debug_hash(&[1.0f32, 2.5]));
    }
}
