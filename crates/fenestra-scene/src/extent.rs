//! How far from the origin a scene may reach: beyond it f32 ray tracing cannot resolve it.

/// The largest coordinate, in metres from the origin, that fenestra ray traces: beyond it f32
/// cannot resolve a scene (both backends tested to 5e12; Embree loses hits by 5e13, and
/// obvhs' tree builder panics near 1e15).
pub const MAX_COORDINATE: f32 = 1e12;

/// Why coordinates reaching `extent` cannot be ray traced, if they cannot.
pub fn extent_error(extent: f32) -> Option<String> {
    (!(extent <= MAX_COORDINATE)).then(|| {
        format!(
            "coordinates reach {extent:e} m, beyond the {MAX_COORDINATE:e} m from the origin that f32 ray tracing resolves (scale the scene down)"
        )
    })
}
