//! A stable 64-bit content hash (FNV-1a) that can digest `Debug` output as a stream, and
//! the fingerprints that large arrays (images, meshes) print as their `Debug` form, so that a
//! scene of millions of triangles and textures is keyed in a fraction of a second.

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
    /// Digests 32-bit words a word at a time (FNV-1a's step on words: four times as fast as
    /// on their bytes, for arrays of floats).
    pub fn update_words(&mut self, words: impl IntoIterator<Item = u32>) {
        for w in words {
            self.0 ^= w as u64;
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

/// The fingerprint of an array's 32-bit words (floats by their bits): what large arrays
/// print for `Debug`.
pub fn fingerprint(words: impl IntoIterator<Item = u32>) -> u64 {
    let mut h = Fnv64::default();
    h.update_words(words);
    h.finish()
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
    use crate::image::Image;
    use crate::Rgb;

    #[test]
    fn an_image_prints_its_size_and_a_fingerprint_that_any_pixel_changes() {
        let mut image = Image::new(1000, 500);
        let before = format!("{image:?}");
        assert!(before.len() < 100, "{before}");
        assert!(before.contains("width: 1000") && before.contains("height: 500"));
        image.set(999, 499, Rgb::new(0.0, 0.0, 1e-30));
        assert_ne!(format!("{image:?}"), before);
        // Words, not bytes: the same words in another order differ.
        assert_ne!(fingerprint([1, 2]), fingerprint([2, 1]));
    }
}
