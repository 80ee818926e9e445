//! Keys of values by their `Debug` form, digested as a stream (large arrays print
//! fingerprints: `fenestra_core::hash`).

pub use fenestra_core::hash::Fnv64;

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
