//! The perfect specular reflector.

use super::checks::albedo;
use fenestra_core::Rgb;

/// Perfect specular reflector.
#[derive(Clone, Debug)]
pub struct Mirror {
    /// Reflectance.
    pub reflectance: Rgb,
}

impl Mirror {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        albedo("reflectance", &self.reflectance)
    }
}
