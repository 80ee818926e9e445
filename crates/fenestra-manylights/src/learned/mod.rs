//! A visibility-aware light sampler learned from the render's own light samples
//! (`light.selection learned`). The light BVH's importance knows power, distance and
//! orientation but not walls: in a stack of rooms it keeps aiming at lights behind floors.
//! Here the scene is cut into cells (a grid of boxes, six normal directions each, and boxes
//! of half their side where the samples are many); in every cell the render's light samples
//! that found light estimate how much each group of lights (a fixed cut through the BVH,
//! plus each light at infinity) contributes there, visibility included; later passes pick a
//! group from that estimate and a light inside it by the BVH.
//! Learning in this spirit: Vévoda et al. 2018 (Bayesian online regression per cache
//! point), Wang et al. 2021 (light-tree cuts learned per voxel); the estimator, the cut and
//! the mixture are ours.
//!
//! At a point p of cell c the probability of light l in group g(l) is
//!
//!   P(l) = (1 - a) P_bvh(l | p) + a L_c(g(l)) P_bvh(l | g(l), p),
//!
//! L_c(g) being the learned share of group g in c (the mean over c's samples of each
//! sample's contribution over its pick probability, summed per group and normalised), and
//! P_bvh(l | g, p) the BVH's descent from g's node. The BVH share keeps every light that can
//! reach p samplable, so nothing learned can bias the image. A point takes the finest cell
//! that learned enough; cells without samples use the BVH alone. Learning happens between
//! passes, from every block's samples in block order: the same learned cells, and pixels,
//! for any number of threads.
//!
//! Learned sky sampling: an environment (not the sun's disk, which is a group of its own) is
//! cut into regions of directions ([`SkyMap`], split by the sky's power) and each region is a
//! group, learned as the others are: through a window a cell learns the regions the window
//! shows it. The environment l_e is picked with the sum of its regions' shares, and its
//! direction w drawn either by the environment's own density p_e or, in proportion to the
//! learned part, uniformly in a region r picked by its share, so that the joint density is
//!
//!   P(l_e, w) = (1 - a) P_base(l_e | p) p_e(w) + a L_c(r(w)) / |r(w)|,
//!
//! |r| being r's solid angle. The first term keeps every direction the sky lights samplable.

use crate::bvh::LightBvh;
use crate::sky::SkyMap;
use fenestra_core::distribution::Distribution1D;
use fenestra_core::{Vec2, Vec3};
use fenestra_render::integrator::LightNextEvent;
use fenestra_render::light::{
    Light, LightContext, LightHit, LightRecords, LightSample, LightSampler, Lights, SplitSuns,
};
use fenestra_scene::Scene;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};

mod options;

pub use options::{Base, LearnedOptions, Suns};

/// Not a group (lights that send nothing).
const NONE: u32 = u32::MAX;

/// Levels of cells: the grid's boxes, and boxes of half their side where the samples of all
/// passes so far fill them (two: [`halves`] finds the stand-ins one level down).
const LEVELS: u32 = 2;

/// Bits of a cell's key for its box's index along an axis.
const AXIS_BITS: u32 = 19;

/// Where a cell's key keeps its level (after three axes and the normal's class).
const LEVEL_SHIFT: u32 = 3 * AXIS_BITS + 3;

/// Samples a cell finer than the grid's boxes needs to be used, in first-pass records per
/// cell (`learned.cell_records`, which sizes the grid's boxes).
const FINE_SAMPLES: u32 = 8;

/// The grid of cells: boxes of one size over the scene, six normal directions each.
#[derive(Clone, Copy, Debug, Default)]
struct Grid {
    lo: Vec3,
    inv_size: f32,
}

impl Grid {
    /// The cell of a point with normal `n` on `level` (0: this grid's boxes; each level
    /// halves them).
    fn key(&self, p: Vec3, n: Vec3, level: u32) -> u64 {
        let q = (p - self.lo) * (self.inv_size * (1 << level) as f32);
        let axis = |v: f32| (v.max(0.0) as u64).min((1 << AXIS_BITS) - 1);
        let a = n.abs();
        let (k, s) = if a.x >= a.y && a.x >= a.z {
            (0, n.x)
        } else if a.y >= a.z {
            (1, n.y)
        } else {
            (2, n.z)
        };
        let class = 2 * k + u64::from(s < 0.0);
        axis(q.x)
            | axis(q.y) << AXIS_BITS
            | axis(q.z) << (2 * AXIS_BITS)
            | class << (3 * AXIS_BITS)
            | u64::from(level) << LEVEL_SHIFT
    }
}

/// The learned distributions of one pass: per cell, its groups in increasing order with
/// their cumulative probabilities.
#[derive(Default)]
struct Table {
    /// The cells.
    grid: Grid,
    /// Open addressing by key: (key, first entry, entries); empty slots have no entries.
    slots: Vec<(u64, u32, u32)>,
    /// (group, cumulative probability) of every cell, cell after cell.
    entries: Vec<(u32, f32)>,
}

impl Table {
    /// The table of `sums` (ordered by cell and group): each group's share in its cell in
    /// proportion to its summed weight. Cells finer than the grid's boxes are kept where they
    /// hold `min_samples` samples.
    fn new(grid: Grid, sums: &[Sum], min_samples: u32) -> Self {
        let mut cells: Vec<(u64, u32, u32)> = Vec::new();
        let mut entries = Vec::with_capacity(sums.len());
        let useful = |s: &&Sum| s.weight > 0.0 && s.weight.is_finite();
        for run in sums.chunk_by(|a, b| a.key == b.key) {
            let key = run[0].key;
            let fine = key >> LEVEL_SHIFT > 0;
            let samples: u32 = run.iter().map(|s| s.samples).sum();
            let total: f64 = run.iter().filter(useful).map(|s| s.weight).sum();
            if (fine && samples < min_samples) || total <= 0.0 || !total.is_finite() {
                continue;
            }
            let first = entries.len() as u32;
            let mut acc = 0.0;
            for s in run.iter().filter(useful) {
                acc += s.weight;
                entries.push((s.group, (acc / total) as f32));
            }
            if let Some(last) = entries.last_mut() {
                last.1 = 1.0;
            }
            cells.push((key, first, entries.len() as u32 - first));
        }
        // A point looks its finest cell up only: the finer cells that did not learn enough
        // stand for their box's.
        let learned_finer = |key: u64| cells.binary_search_by_key(&key, |c| c.0).is_ok();
        let stand_ins: Vec<(u64, u32, u32)> = cells
            .iter()
            .filter(|c| c.0 >> LEVEL_SHIFT == 0)
            .flat_map(|&(key, first, len)| halves(key).map(|half| (half, first, len)))
            .filter(|c| !learned_finer(c.0))
            .collect();
        cells.extend(stand_ins);
        let capacity = (2 * cells.len()).next_power_of_two().max(2);
        let mut slots = vec![(0, 0, 0); capacity];
        for cell in cells {
            let mut s = slot(cell.0, capacity);
            while slots[s].2 != 0 {
                s = (s + 1) & (capacity - 1);
            }
            slots[s] = cell;
        }
        Table {
            grid,
            slots,
            entries,
        }
    }

    /// The entries of the cell of a point with normal `n`, if it learned anything.
    fn at(&self, p: Vec3, n: Vec3) -> Option<&[(u32, f32)]> {
        if self.entries.is_empty() {
            return None;
        }
        self.cell(self.grid.key(p, n, LEVELS - 1))
    }

    /// The entries of cell `key`, if it learned anything.
    fn cell(&self, key: u64) -> Option<&[(u32, f32)]> {
        let mask = self.slots.len() - 1;
        let mut s = slot(key, self.slots.len());
        loop {
            let (k, first, len) = self.slots[s];
            if len == 0 {
                return None;
            }
            if k == key {
                return Some(&self.entries[first as usize..(first + len) as usize]);
            }
            s = (s + 1) & mask;
        }
    }
}

/// The keys of the eight boxes of half the side of cell `key`'s (its normal direction's).
fn halves(key: u64) -> [u64; 8] {
    let mask = (1 << AXIS_BITS) - 1;
    let axis = |a: u32| (key >> (a * AXIS_BITS)) & mask;
    let rest = key >> (3 * AXIS_BITS) & 7;
    let level = (key >> LEVEL_SHIFT) + 1;
    std::array::from_fn(|i| {
        let half = |a: u32| (2 * axis(a) + (i as u64 >> a & 1)).min(mask);
        half(0)
            | half(1) << AXIS_BITS
            | half(2) << (2 * AXIS_BITS)
            | rest << (3 * AXIS_BITS)
            | level << LEVEL_SHIFT
    })
}

/// The home slot of `key` in a table of `capacity` (a power of two) slots.
fn slot(key: u64, capacity: usize) -> usize {
    (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 32) as usize & (capacity - 1)
}

/// A group picked with `u` among `within`, entries of a cell after cumulative probability
/// `below`, in proportion to their probabilities: (group, probability, `u` rescaled).
fn pick_within(within: &[(u32, f32)], below: f32, u: f32) -> (u32, f32, f32) {
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
fn entries_of(entries: &[(u32, f32)], groups: Groups) -> (&[(u32, f32)], f32) {
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
fn groups_pmf(entries: &[(u32, f32)], groups: Groups) -> f32 {
    match entries_of(entries, groups) {
        (&[], _) => 0.0,
        (within, below) => within[within.len() - 1].1 - below,
    }
}

/// The groups from `.0` up to `.1` (excluded): a light's (one, or an environment's regions).
type Groups = (u32, u32);

/// An environment whose regions are groups.
struct Sky {
    /// The environment light.
    light: usize,
    /// Its first region's group.
    first: u32,
    /// Its regions.
    map: SkyMap,
}

/// Light sampling by the learned sampler with `options` (its suns split apart if asked).
pub fn light_sampling(options: LearnedOptions) -> LightNextEvent {
    let split = options.suns == Suns::Split;
    let next_event = LightNextEvent::with_learning_sampler(options.name(), move |s| {
        let learned = Box::new(LearnedLights::new(&s.scene, &s.lights, options));
        if split {
            Box::new(SplitSuns::new(learned, &s.lights))
        } else {
            learned
        }
    });
    if split {
        next_event.taking_several()
    } else {
        next_event
    }
}

/// The learned light sampler.
pub struct LearnedLights {
    bvh: LightBvh,
    options: LearnedOptions,
    /// The scene's bounding box: its low corner and diagonal.
    lo: Vec3,
    diagonal: f32,
    /// The cells, sized from the first pass's records.
    grid: OnceLock<Grid>,
    /// Lights by emitted power (the power base).
    power: Distribution1D,
    /// The BVH node of each group of the tree and its depth; groups after these are lights
    /// at infinity.
    group_node: Vec<(usize, u32)>,
    /// Per BVH node: its group, or [`NONE`] for nodes not in the cut.
    node_group: Vec<u32>,
    /// Per light: its group (an environment of [`LearnedLights::skies`]: its first region's),
    /// or [`NONE`].
    light_group: Vec<u32>,
    /// The light of each group after the tree's (lights at infinity, a group per region of
    /// an environment of `skies`).
    group_light: Vec<usize>,
    /// The environments whose regions are groups.
    skies: Vec<Sky>,
    /// Tables learned so far (the first is empty: the BVH alone); `current` is in use.
    tables: Vec<OnceLock<Table>>,
    current: AtomicUsize,
    /// What the passes learned so far: per level of cells, per (cell, group), the summed
    /// weights of the samples that found light, and their number.
    sums: Mutex<LevelSums>,
}

/// Per level of cells, per (cell, group): summed weights and samples.
type LevelSums = [HashMap<(u64, u32), (f64, u32)>; LEVELS as usize];

/// The samples of one group in one cell that found light: their summed weights, and their
/// number.
struct Sum {
    key: u64,
    group: u32,
    weight: f64,
    samples: u32,
}

impl LearnedLights {
    /// The sampler for `lights` of `scene`, before it has learned anything.
    pub fn new(scene: &Scene, lights: &Lights, options: LearnedOptions) -> Self {
        let bvh = LightBvh::new(scene, lights);
        let group_node = cut(&bvh, options.groups.max(1));
        let mut node_group = vec![NONE; bvh.node_count()];
        let mut light_group = vec![NONE; lights.lights.len()];
        for (g, &(node, _)) in group_node.iter().enumerate() {
            node_group[node] = g as u32;
            let mut stack = vec![node];
            while let Some(n) = stack.pop() {
                match bvh.children(n) {
                    Some((a, b)) => stack.extend([a, b]),
                    None => light_group[bvh.leaf_light(n).expect("leaf")] = g as u32,
                }
            }
        }
        let mut group_light = Vec::new();
        let mut skies = Vec::new();
        for &light in bvh.infinite() {
            let group = (group_node.len() + group_light.len()) as u32;
            light_group[light] = group;
            let regions = match &lights.lights[light] {
                l @ Light::Environment(_) if !l.is_compact() && options.sky_regions > 0 => {
                    let map = SkyMap::new(lights, light, options.sky_regions);
                    let count = map.regions.len();
                    skies.push(Sky {
                        light,
                        first: group,
                        map,
                    });
                    count
                }
                _ => 1,
            };
            group_light.extend(std::iter::repeat_n(light, regions));
        }
        // Power only for lights the groups hold, so both distributions cover the same lights.
        let powers: Vec<f32> = lights
            .lights
            .iter()
            .zip(&light_group)
            .map(|(l, &g)| if g == NONE { 0.0 } else { l.power(scene) })
            .collect();
        let (lo, hi) = scene.bounds();
        let tables: Vec<OnceLock<Table>> = (0..=options.passes).map(|_| OnceLock::new()).collect();
        let _ = tables[0].set(Table::default());
        LearnedLights {
            bvh,
            options,
            lo,
            diagonal: (hi - lo).length().max(1e-6),
            grid: OnceLock::new(),
            power: Distribution1D::new(if powers.is_empty() { &[0.0] } else { &powers }),
            group_node,
            node_group,
            light_group,
            group_light,
            skies,
            tables,
            current: AtomicUsize::new(0),
            sums: Mutex::default(),
        }
    }

    /// Cells that have learned something so far.
    pub fn cells_learned(&self) -> usize {
        self.table().slots.iter().filter(|s| s.2 > 0).count()
    }

    fn table(&self) -> &Table {
        self.tables[self.current.load(Ordering::Acquire)]
            .get()
            .expect("the current table is set")
    }

    /// The groups of `light`: its own, or its regions', or `None`.
    fn groups(&self, light: usize) -> Option<Groups> {
        let first = *self.light_group.get(light).filter(|&&g| g != NONE)?;
        Some(match self.sky(light) {
            Some(sky) => (first, first + sky.map.regions.len() as u32),
            None => (first, first + 1),
        })
    }

    /// The environment `light` if its regions are groups.
    fn sky(&self, light: usize) -> Option<&Sky> {
        self.skies.iter().find(|s| s.light == light)
    }

    /// The group a light sample towards `light` along `wi` counts for.
    fn group_of(&self, light: usize, wi: Vec3) -> u32 {
        match self.sky(light) {
            Some(sky) => sky.first + sky.map.region_of(wi) as u32,
            None => self.light_group[light],
        }
    }

    /// P(l_e, w) of the module's equation for the environment of `sky` learned in a cell with
    /// `entries`: the environment's density `own` of w given.
    fn sky_pdf(
        &self,
        ctx: &LightContext,
        entries: &[(u32, f32)],
        sky: &Sky,
        wi: Vec3,
        own: f32,
    ) -> f32 {
        let a = self.options.mix;
        let (base, _) = self.base_and_below(ctx, sky.light, sky.first);
        let r = sky.map.region_of(wi);
        let group = sky.first + r as u32;
        let learned = groups_pmf(entries, (group, group + 1)) / sky.map.regions[r].solid_angle();
        (1.0 - a) * base * own + a * learned
    }

    /// Probability of `light` from its group's node down, at `ctx`.
    fn below_group(&self, ctx: &LightContext, light: usize, group: u32) -> f32 {
        match self.group_node.get(group as usize) {
            Some(&(node, depth)) => self
                .bvh
                .replay_from(light, node, depth, 1.0, ctx, |_, _| true),
            None => 1.0,
        }
    }

    /// The base's probability of `light` at `ctx` and the light's probability from its
    /// group's node down.
    fn base_and_below(&self, ctx: &LightContext, light: usize, group: u32) -> (f32, f32) {
        match self.options.base {
            Base::Power => (
                self.power.discrete_pmf(light),
                self.below_group(ctx, light, group),
            ),
            Base::Bvh => {
                let infinite = self.bvh.infinite_pmf(light);
                if infinite > 0.0 {
                    return (infinite, 1.0);
                }
                let mut at_group = 0.0;
                let full = self.bvh.replay(light, ctx, |node, pmf| {
                    if self.node_group[node] != NONE {
                        at_group = pmf;
                    }
                    true
                });
                (full, if at_group > 0.0 { full / at_group } else { 0.0 })
            }
        }
    }

    /// A light by the base at `ctx`: (light, its group, base probability, probability from
    /// the group's node down), found on the way where the base is the BVH.
    fn sample_base(&self, ctx: &LightContext, u: f32) -> Option<(usize, u32, f32, f32)> {
        match self.options.base {
            Base::Power => {
                let (light, base, _) = self.power.sample_discrete(u);
                let group = self.light_group[light];
                Some((light, group, base, self.below_group(ctx, light, group)))
            }
            Base::Bvh => {
                let p_tree = self.bvh.tree_probability();
                if u >= p_tree {
                    let (light, full) = self.bvh.sample(ctx, u)?;
                    return Some((light, self.light_group[light], full, 1.0));
                }
                let mut at_group = 0.0;
                let (light, full) = self.bvh.descend(0, p_tree, ctx, u / p_tree, |node, pmf| {
                    if self.node_group[node] != NONE {
                        at_group = pmf;
                    }
                })?;
                Some((light, self.light_group[light], full, full / at_group))
            }
        }
    }

    /// P(l) of the module's equation at a point of a cell with `entries`.
    fn mixed_pmf(&self, ctx: &LightContext, entries: &[(u32, f32)], light: usize) -> f32 {
        let Some(groups) = self.groups(light) else {
            return 0.0;
        };
        let (base, below) = self.base_and_below(ctx, light, groups.0);
        let a = self.options.mix;
        (1.0 - a) * base + a * groups_pmf(entries, groups) * below
    }
}

/// The finest grid whose boxes (the scene's diagonal over a power of two) hold `per_cell`
/// of `points` on average, counting each normal direction's cell apart.
fn grid_for(points: &[(Vec3, Vec3)], lo: Vec3, diagonal: f32, per_cell: u32) -> Grid {
    let wanted = (points.len() / per_cell.max(1) as usize).max(1);
    let mut keys = Vec::with_capacity(points.len());
    let mut grid = Grid {
        lo,
        inv_size: 1.0 / diagonal,
    };
    for k in 1..=AXIS_BITS - (LEVELS - 1) {
        let finer = Grid {
            lo,
            inv_size: (1u32 << k) as f32 / diagonal,
        };
        keys.clear();
        keys.extend(points.iter().map(|&(p, n)| finer.key(p, n, 0)));
        keys.sort_unstable();
        keys.dedup();
        if keys.len() > wanted {
            break;
        }
        grid = finer;
    }
    grid
}

/// A cut of `groups` nodes (at most) through the BVH, with their depths: starting from the
/// root, the node of largest extent is replaced by its children until there are `groups`
/// (lights at a point or within a small region stay together, far-apart ones part).
fn cut(bvh: &LightBvh, groups: usize) -> Vec<(usize, u32)> {
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

impl LightSampler for LearnedLights {
    fn sample(&self, ctx: &LightContext, u: f32) -> Option<(usize, f32)> {
        let Some(entries) = self.table().at(ctx.p, ctx.n) else {
            return self.bvh.sample(ctx, u);
        };
        let a = self.options.mix;
        // Either branch finds the light's base probability and its learned one (its group's
        // times its probability from the group's node down) on the way, or at little cost.
        let (light, base, learned) = if u < a {
            let (group, p_group, u) = pick_within(entries, 0.0, u / a);
            match self.group_node.get(group as usize) {
                Some(&(node, _)) => {
                    let (light, below) = self.bvh.descend(node, 1.0, ctx, u, |_, _| {})?;
                    let base = match self.options.base {
                        Base::Power => self.power.discrete_pmf(light),
                        Base::Bvh => self.bvh.replay(light, ctx, |n, _| n != node) * below,
                    };
                    (light, base, p_group * below)
                }
                None => {
                    let light = self.group_light[group as usize - self.group_node.len()];
                    let base = match self.options.base {
                        Base::Power => self.power.discrete_pmf(light),
                        Base::Bvh => self.bvh.infinite_pmf(light),
                    };
                    let groups = self.groups(light)?;
                    (light, base, groups_pmf(entries, groups))
                }
            }
        } else {
            let u = ((u - a) / (1.0 - a)).min(1.0 - f32::EPSILON);
            let (light, _, base, below) = self.sample_base(ctx, u)?;
            (
                light,
                base,
                groups_pmf(entries, self.groups(light)?) * below,
            )
        };
        let pmf = (1.0 - a) * base + a * learned;
        (pmf > 0.0).then_some((light, pmf))
    }

    fn pmf(&self, ctx: &LightContext, light: usize) -> f32 {
        match self.table().at(ctx.p, ctx.n) {
            Some(entries) => self.mixed_pmf(ctx, entries, light),
            None => self.bvh.pmf(ctx, light),
        }
    }

    /// An environment of `skies` draws its direction by its own density or, in proportion
    /// to what its regions learned, uniformly in a region picked by its share.
    fn sample_li(
        &self,
        scene: &Scene,
        lights: &Lights,
        ctx: &LightContext,
        pick: (usize, f32),
        u: Vec2,
    ) -> Option<LightSample> {
        let learned = self.sky(pick.0).zip(self.table().at(ctx.p, ctx.n));
        let Some((sky, entries)) = learned else {
            return Some(
                lights.lights[pick.0]
                    .sample_li(scene, ctx.p, u)?
                    .picked(pick.1),
            );
        };
        let light = &lights.lights[sky.light];
        let a = self.options.mix;
        let (base, _) = self.base_and_below(ctx, sky.light, sky.first);
        let groups = (sky.first, sky.first + sky.map.regions.len() as u32);
        let (within, below) = entries_of(entries, groups);
        let regions = within.last().map_or(0.0, |e| e.1 - below);
        // The learned part's share of the environment's pick.
        let q = a * regions / ((1.0 - a) * base + a * regions);
        let wi = if u.x < q {
            let (group, _, v) = pick_within(within, below, u.x / q);
            let region = &sky.map.regions[(group - sky.first) as usize];
            region.sample(Vec2::new(v, u.y))
        } else {
            let v = ((u.x - q) / (1.0 - q)).min(1.0 - f32::EPSILON);
            light.sample_li(scene, ctx.p, Vec2::new(v, u.y))?.wi
        };
        let own = light.pdf_li(scene, ctx.p, wi, LightHit::Escaped);
        let pdf = self.sky_pdf(ctx, entries, sky, wi, own);
        (pdf > 0.0).then(|| LightSample {
            wi,
            li: light.le(LightHit::Escaped, wi),
            pdf,
            point: None,
            delta: false,
        })
    }

    fn pdf_li(
        &self,
        scene: &Scene,
        lights: &Lights,
        ctx: &LightContext,
        light: usize,
        wi: Vec3,
        hit: LightHit,
    ) -> f32 {
        let own = lights.lights[light].pdf_li(scene, ctx.p, wi, hit);
        match self.sky(light).zip(self.table().at(ctx.p, ctx.n)) {
            Some((sky, entries)) => self.sky_pdf(ctx, entries, sky, wi, own),
            None => self.pmf(ctx, light) * own,
        }
    }

    fn learns(&self, pass: u32) -> bool {
        pass < self.options.passes
    }

    fn learn(&self, blocks: &[LightRecords]) {
        let records = || blocks.iter().flat_map(|b| &b.records);
        let grid = *self.grid.get_or_init(|| {
            let points: Vec<(Vec3, Vec3)> = records().map(|r| (r.p, r.n)).collect();
            grid_for(&points, self.lo, self.diagonal, self.options.cell_records)
        });
        let mut sums = self.sums.lock().expect("learning is not poisoned");
        // A level per thread, in sample order: the same sums whatever the threads.
        sums.par_iter_mut().enumerate().for_each(|(level, sums)| {
            for r in records() {
                let group = self.group_of(r.light as usize, r.wi);
                if group != NONE && r.weight > 0.0 && r.weight.is_finite() {
                    let key = grid.key(r.p, r.n, level as u32);
                    let sum = sums.entry((key, group)).or_default();
                    sum.0 += f64::from(r.weight);
                    sum.1 += 1;
                }
            }
        });
        let next = self.current.load(Ordering::Acquire) + 1;
        if let Some(slot) = self.tables.get(next) {
            let fine = FINE_SAMPLES.saturating_mul(self.options.cell_records);
            let mut sorted: Vec<Sum> = sums
                .iter()
                .flatten()
                .map(|(&(key, group), &(weight, samples))| Sum {
                    key,
                    group,
                    weight,
                    samples,
                })
                .collect();
            sorted.par_sort_unstable_by_key(|s| (s.key, s.group));
            let _ = slot.set(Table::new(grid, &sorted, fine));
            self.current.store(next, Ordering::Release);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_render::options::Options;

    /// Sums of `groups(cell)` groups in each of `cells`, group g weighing 1 + g, with
    /// `samples` samples each.
    fn sums_of(cells: &[u64], groups: impl Fn(u64) -> u32, samples: u32) -> Vec<Sum> {
        let mut sums: Vec<Sum> = cells
            .iter()
            .flat_map(|&key| {
                (0..groups(key)).map(move |group| Sum {
                    key,
                    group,
                    weight: 1.0 + group as f64,
                    samples,
                })
            })
            .collect();
        sums.sort_by_key(|s| (s.key, s.group));
        sums
    }

    #[test]
    fn tables_find_every_cell_they_learned_and_no_other() {
        let cells: Vec<u64> = (0..300u64).map(|c| c * 7919).collect();
        let groups = |key: u64| ((key / 7919) % 5) as u32;
        let table = Table::new(Grid::default(), &sums_of(&cells, groups, 1), 1);
        for &key in &cells {
            let found = table.cell(key);
            let groups = groups(key);
            if groups == 0 {
                assert!(found.is_none());
                continue;
            }
            let entries = found.expect("a learned cell");
            let total: f64 = (0..groups).map(|g| 1.0 + g as f64).sum();
            for g in 0..groups {
                let p = groups_pmf(entries, (g, g + 1));
                assert!((f64::from(p) - (1.0 + g as f64) / total).abs() < 1e-6);
                // Picking at the middle of its interval gives the group back.
                let mid = entries[g as usize].1 - p / 2.0;
                assert_eq!(pick_within(entries, 0.0, mid).0, g);
            }
            assert_eq!(groups_pmf(entries, (groups, groups + 1)), 0.0);
        }
        assert!(table.cell(12345).is_none());
    }

    #[test]
    fn points_take_the_finest_cell_that_learned_enough() {
        let grid = Grid {
            lo: Vec3::ZERO,
            inv_size: 1.0,
        };
        // Two points in one box of the grid, in different half boxes.
        let (a, b) = (Vec3::splat(0.25), Vec3::splat(0.75));
        let coarse = grid.key(a, Vec3::Z, 0);
        assert_eq!(coarse, grid.key(b, Vec3::Z, 0));
        let (fine_a, fine_b) = (grid.key(a, Vec3::Z, 1), grid.key(b, Vec3::Z, 1));
        assert_ne!(fine_a, fine_b);
        // The box learned group 0 from 19 samples, a's half box group 1 from 5, b's group 2
        // from 3.
        let mut sums = sums_of(&[coarse], |_| 1, 19);
        sums.extend(sums_of(&[fine_a], |_| 2, 5).into_iter().skip(1));
        sums.extend(sums_of(&[fine_b], |_| 3, 3).into_iter().skip(2));
        sums.sort_by_key(|s| (s.key, s.group));
        let table = Table::new(grid, &sums, 4);
        let groups = |p: Vec3| table.at(p, Vec3::Z).expect("learned").iter().map(|e| e.0);
        assert!(groups(a).eq([1]), "a's half box has 5 samples of 4 needed");
        assert!(groups(b).eq([0]), "b's has 3, so b takes the box");
        assert!(groups(Vec3::new(0.75, 0.25, 0.25)).eq([0]));
    }

    #[test]
    fn a_box_has_the_half_boxes_of_its_points() {
        let grid = Grid {
            lo: Vec3::new(-3.0, -1.0, 2.0),
            inv_size: 0.7,
        };
        let mut rng = fenestra_core::Rng::new(7);
        for _ in 0..2000 {
            let p = grid.lo + Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 40.0;
            let n = fenestra_core::warp::square_to_uniform_sphere(rng.next_2d());
            let halves = halves(grid.key(p, n, 0));
            assert!(halves.contains(&grid.key(p, n, 1)), "{p} {n}");
            // ... and no other box's, nor another normal direction's.
            assert!(!halves.contains(&grid.key(p + Vec3::X / grid.inv_size, n, 1)));
            assert!(!halves.contains(&grid.key(p, -n, 1)));
        }
    }

    #[test]
    fn cells_tell_normals_and_boxes_apart() {
        let grid = Grid {
            lo: Vec3::ZERO,
            inv_size: 2.0,
        };
        let p = Vec3::new(0.3, 0.3, 0.3);
        let key = |p, n| grid.key(p, n, 0);
        assert_ne!(key(p, Vec3::Z), key(p, -Vec3::Z));
        assert_ne!(key(p, Vec3::Z), key(p, Vec3::X));
        assert_eq!(key(p, Vec3::Z), key(p + Vec3::splat(0.1), Vec3::Z));
        assert_ne!(key(p, Vec3::Z), key(p + Vec3::splat(0.3), Vec3::Z));
        // The next level halves the boxes (0.2 and 0.3 share a box of 1/2, not of 1/4),
        // and its cells are its own.
        let q = p - Vec3::splat(0.1);
        assert_eq!(key(p, Vec3::Z), key(q, Vec3::Z));
        assert_ne!(grid.key(p, Vec3::Z, 1), grid.key(q, Vec3::Z, 1));
        assert_ne!(grid.key(p, Vec3::Z, 1), key(p, Vec3::Z));
    }

    #[test]
    fn cells_are_as_fine_as_the_records_allow() {
        // 4,096 points on a floor of side 1 facing up: 2^k cells a side hold 4096 / 4^k.
        let points: Vec<(Vec3, Vec3)> = (0..4096)
            .map(|i| {
                let (x, y) = ((i % 64) as f32 + 0.5, (i / 64) as f32 + 0.5);
                (Vec3::new(x / 64.0, y / 64.0, 0.0), Vec3::Z)
            })
            .collect();
        let side = |g: Grid| g.inv_size.recip();
        // Diagonal 1: boxes of 1/2^k. 16 a cell: 256 cells, 1/16 a side.
        let g = grid_for(&points, Vec3::ZERO, 1.0, 16);
        assert_eq!(side(g), 1.0 / 16.0);
        let g = grid_for(&points, Vec3::ZERO, 1.0, 64);
        assert_eq!(side(g), 1.0 / 8.0);
        // Fewer points than one cell wants (the first ten, x up to 0.15): the finest grid
        // that keeps them in one cell.
        let g = grid_for(&points[..10], Vec3::ZERO, 1.0, 64);
        assert_eq!(side(g), 0.25);
    }

    #[test]
    fn options_that_could_bias_or_mean_nothing_are_refused() {
        let ok = LearnedOptions::default();
        assert!(ok.check().is_ok());
        let e = LearnedOptions { mix: 1.0, ..ok }
            .check()
            .expect_err("a mix of 1 leaves no light tree");
        assert!(e.to_string().starts_with("learned.mix must be"), "{e}");
        assert!(LearnedOptions {
            cell_records: 0,
            ..ok
        }
        .check()
        .is_err());
        assert!(LearnedOptions { groups: 0, ..ok }.check().is_err());
        assert!(LearnedOptions {
            passes: u32::MAX,
            ..ok
        }
        .check()
        .is_err());
    }
}
