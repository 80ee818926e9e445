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
use fenestra_core::Vec3;
use fenestra_render::integrator::LightNextEvent;
use fenestra_render::light::{Light, LightContext, LightSampler, Lights, SplitSuns};
use fenestra_scene::Scene;
use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};

mod cells;
mod groups;
mod options;
mod sampler;
#[cfg(test)]
mod tests;

use cells::{Grid, Table, LEVELS};
use groups::{cut, groups_pmf, Groups, NONE};
pub use options::{Base, LearnedOptions, Suns};

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
