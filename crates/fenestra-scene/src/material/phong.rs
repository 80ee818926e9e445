//! Energy-normalised Phong.

use super::checks::non_negative;
use fenestra_core::Rgb;

/// Energy-normalised Phong: kd/pi + ks (n+2)/(2 pi) cos^n(alpha).
#[derive(Clone, Debug)]
pub struct Phong {
    /// kd.
    pub diffuse: Rgb,
    /// ks.
    pub specular: Rgb,
    /// The lobe exponent n.
    pub exponent: f32,
}

impl Phong {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        if !non_negative(&self.diffuse) || !non_negative(&self.specular) {
            return Some("Phong reflectances must be finite and non-negative".into());
        }
        let n = self.exponent;
        (!(n.is_finite() && n >= 0.0)).then(|| format!("Phong exponent {n} must be >= 0"))
    }
}
