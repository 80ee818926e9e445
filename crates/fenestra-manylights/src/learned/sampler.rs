//! The learned sampler as a light sampler: picking a light at a point, and the probability
//! of a pick (the mixture of the module's equations).

use super::cells::{grid_for, Sum, Table, FINE_SAMPLES};
use super::groups::{entries_of, groups_pmf, pick_within, NONE};
use super::{Base, LearnedLights};
use fenestra_core::{Vec2, Vec3};
use fenestra_render::light::{
    LightContext, LightHit, LightRecords, LightSample, LightSampler, Lights,
};
use fenestra_scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::Ordering;

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
