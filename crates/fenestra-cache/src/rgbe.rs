//! Ward's RGBE: three 8-bit mantissas sharing one 8-bit exponent, the radiance of an L-tree
//! sample in four bytes (seed 003 §2.4.3).

use fenestra_core::Rgb;

/// Radiance in RGBE. Channels are relative to the largest: each is within 1/128 of the
/// largest channel's value of the radiance encoded (negative values encode as 0).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Rgbe(pub [u8; 4]);

impl Rgbe {
    /// Encodes `c` (non-finite and negative channels count as 0; values beyond 2^127 saturate).
    pub fn encode(c: Rgb) -> Rgbe {
        let clean = |v: f32| if v.is_finite() && v > 0.0 { v } else { 0.0 };
        let (r, g, b) = (clean(c.r), clean(c.g), clean(c.b));
        let max = r.max(g).max(b);
        if max < 1e-32 {
            return Rgbe([0; 4]);
        }
        // The largest float below 2^127: its exponent byte is 255.
        let max = max.min(f32::from_bits((253 << 23) | 0x7f_ffff));
        // max = m 2^e with m in [0.5, 1): from the float's own exponent field.
        let e = ((max.to_bits() >> 23) & 0xff) as i32 - 126;
        let scale = 256.0 / exp2i(e);
        let q = |v: f32| (v.min(max) * scale).min(255.0) as u8;
        Rgbe([q(r), q(g), q(b), (e + 128) as u8])
    }

    /// The radiance, each channel at the middle of its mantissa step (0 stays 0).
    pub fn decode(self) -> Rgb {
        let [r, g, b, e] = self.0;
        if e == 0 {
            return Rgb::ZERO;
        }
        let f = exp2i(e as i32 - 136);
        let d = |v: u8| if v == 0 { 0.0 } else { (v as f32 + 0.5) * f };
        Rgb::new(d(r), d(g), d(b))
    }
}

/// 2^e for -149 <= e <= 127 without a library call.
fn exp2i(e: i32) -> f32 {
    if e >= -126 {
        f32::from_bits(((e + 127) as u32) << 23)
    } else {
        f32::from_bits(1u32 << (e + 149))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decoding_is_within_a_mantissa_step_of_the_largest_channel() {
        let mut rng = fenestra_core::Rng::new(0x1234_5678);
        let mut next = || rng.next_f32();
        for _ in 0..100_000 {
            let scale = 10f32.powf(next() * 30.0 - 15.0);
            let c = Rgb::new(next() * scale, next() * scale, next() * scale * next());
            let d = Rgbe::encode(c).decode();
            let max = c.r.max(c.g).max(c.b);
            for (a, b) in [(c.r, d.r), (c.g, d.g), (c.b, d.b)] {
                assert!((a - b).abs() <= max / 128.0 * 1.0001, "{c:?} -> {d:?}");
            }
        }
    }

    #[test]
    fn zero_negative_and_non_finite_encode_as_black() {
        assert_eq!(Rgbe::encode(Rgb::ZERO).decode(), Rgb::ZERO);
        let d = Rgbe::encode(Rgb::new(-1.0, f32::NAN, 2.0)).decode();
        assert_eq!((d.r, d.g), (0.0, 0.0));
        assert!((d.b - 2.0).abs() <= 2.0 / 256.0);
        let big = Rgbe::encode(Rgb::splat(f32::INFINITY)).decode();
        assert_eq!(big, Rgb::ZERO);
    }
}
