//! The groups the learned sampler picks among: a fixed cut through the light BVH (plus each
//! light at infinity, and each region of an environment), and picking among a cell's learned
//! entries of them.

use crate::bvh::LightBvh;

/// Not a group (lights that send nothing).
pub(super) const NONE: u32 = u32::MAX;

/// A group picked with `u` among `within`, entries of a cell after cumulative probability
/// `below`, in proportion to their probabilities: (group, probability, `u` rescaled).
pub(super) fn pick_within(within: &[(u32, f32)], below: f32, u: f32) -> (u32, f32, f32) {
    let total = within[within.len() - 1].1 - below;
    let target = below + u * total;
    let i = within
        .partition_point(|&(_, c)| c <= target)
        .min(within.len() - 1);
    let start = if i == 0 { below } else { within[i - 1].1 };
    let p = within[i].1 - start;
    let v = ((target - start) / p).clamp(0.0, 1.0 - f32::EPSILON);
    (within[i].0, p / total, v)
}

/// The entries of `groups` (a range) among a cell's entries, and the cumulative probability
/// before them.
pub(super) fn entries_of(entries: &[(u32, f32)], groups: Groups) -> (&[(u32, f32)], f32) {
    let start = entries.partition_point(|&(g, _)| g < groups.0);
    let end = start + entries[start..].partition_point(|&(g, _)| g < groups.1);
    let below = if start == 0 {
        0.0
    } else {
        entries[start - 1].1
    };
    (&entries[start..end], below)
}

/// Probability of `groups` (a range) in a cell's entries.
pub(super) fn groups_pmf(entries: &[(u32, f32)], groups: Groups) -> f32 {
    match entries_of(entries, groups) {
        (&[], _) => 0.0,
        (within, below) => within[within.len() - 1].1 - below,
    }
}

/// The groups from `.0` up to `.1` (excluded): a light's (one, or an environment's regions).
pub(super) type Groups = (u32, u32);

/// A cut of `groups` nodes (at most) through the BVH, with their depths: starting from the
/// root, the node of largest extent is replaced by its children until there are `groups`
/// (lights at a point or within a small region stay together, far-apart ones part).
pub(super) fn cut(bvh: &LightBvh, groups: usize) -> Vec<(usize, u32)> {
    if bvh.node_count() == 0 {
        return Vec::new();
    }
    let mut cut = vec![(0usize, 0u32)];
    while cut.len() < groups {
        let widest = cut
            .iter()
            .enumerate()
            .filter(|(_, &(n, _))| bvh.children(n).is_some())
            .max_by(|a, b| {
                bvh.extent(a.1 .0)
                    .total_cmp(&bvh.extent(b.1 .0))
                    .then(b.0.cmp(&a.0))
            });
        let Some((i, &(node, depth))) = widest else {
            break;
        };
        let (a, b) = bvh.children(node).expect("interior");
        cut[i] = (a, depth + 1);
        cut.push((b, depth + 1));
    }
    cut.sort_unstable();
    cut
}
