//! The points a block's pixels are shaded at: sub-pixel regions of similar eye-ray hits
//! (seed 004 §3.6), each with its cut through the light clusters (§3.5.1).

use fenestra_core::Vec3;
use fenestra_render::bsdf::Bsdf;
use fenestra_scene::SurfaceInteraction;

/// Where an eye ray met a surface.
pub(super) struct Shade {
    pub(super) si: SurfaceInteraction,
    pub(super) bsdf: Bsdf,
    /// Towards the eye.
    pub(super) wo: Vec3,
}

/// A point to shade: a region's eye-ray hits (its first one first), which its light samples
/// take in turn, with one cut, PDF and statistics for all.
pub(super) struct Point {
    pub(super) hits: Vec<Shade>,
    /// Normal on the eye's side.
    pub(super) n: Vec3,
    pub(super) class: usize,
    /// Share of the pixel.
    pub(super) area: f32,
    /// The clusters of its cut (forest nodes; past the forest's nodes, lights at infinity).
    pub(super) cut: Vec<u32>,
    /// The seed's reference: its PDF over the cut, the same in every pass (empty for ias).
    pub(super) irradiance: Vec<f32>,
    /// At points that take BSDF samples too (module `bsdf_samples`), the cut's clusters
    /// sorted, with their index in the cut; empty at points that sample lights only.
    pub(super) lookup: Vec<(u32, u32)>,
}

/// The index of the point of the largest region.
pub(super) fn largest(points: &[Point]) -> usize {
    (0..points.len())
        .max_by(|&a, &b| points[a].area.total_cmp(&points[b].area).then(b.cmp(&a)))
        .unwrap_or(0)
}

/// A cut's clusters sorted, each with its index in the cut (to find a light's cluster).
pub(super) fn cut_lookup(cut: &[u32]) -> Vec<(u32, u32)> {
    let mut lookup: Vec<(u32, u32)> = cut
        .iter()
        .enumerate()
        .map(|(i, &c)| (c, i as u32))
        .collect();
    lookup.sort_unstable();
    lookup
}
