//! The checks every kind's parameters share.

use fenestra_core::Rgb;

/// Whether `c` is a finite, non-negative colour.
pub(super) fn non_negative(c: &Rgb) -> bool {
    c.is_finite() && c.r >= 0.0 && c.g >= 0.0 && c.b >= 0.0
}

/// `None` if the albedo `c` lies in [0, 1], else why not, naming it `what`.
pub(super) fn albedo(what: &str, c: &Rgb) -> Option<String> {
    (!non_negative(c) || c.max_component() > 1.0)
        .then(|| format!("{what} {c:?} must lie in [0, 1]"))
}

/// `None` if the index of refraction `eta` is positive, else why not.
pub(super) fn index_of_refraction(eta: f32) -> Option<String> {
    (!(eta.is_finite() && eta > 0.0)).then(|| format!("index of refraction {eta} must be positive"))
}

/// Whether a roughness (GGX alpha, Ward alpha) is usable.
pub(super) fn roughness_ok(alpha: f32) -> bool {
    alpha.is_finite() && alpha > 0.0
}
