//! Choosing which light to sample at a shading point. An integrator owns its light sampler;
//! learned samplers (seed 004's adaptive cuts, light trees) implement the same trait and see
//! the shading point's pixel, block and pass through [`LightContext`].

use super::{LightHit, LightRecords, LightSample, Lights};
use crate::render_scene::RenderScene;
use crate::sample_context::SampleContext;
use fenestra_core::distribution::Distribution1D;
use fenestra_core::{Vec2, Vec3};
use fenestra_scene::Scene;

/// What a light sampler sees of a shading point.
#[derive(Clone, Copy, Debug)]
pub struct LightContext<'a> {
    /// The point.
    pub p: Vec3,
    /// Its shading normal.
    pub n: Vec3,
    /// The sample being taken: pixel, 8x8 block, pass.
    pub sample: &'a SampleContext,
}

/// Picks lights for next-event estimation.
pub trait LightSampler: Send + Sync {
    /// Picks a light at `ctx`: (light index, probability).
    fn sample(&self, ctx: &LightContext, u: f32) -> Option<(usize, f32)>;
    /// Probability that `sample` picks `light` at `ctx` (for a sampler that picks several,
    /// the probability that the pick standing for `light`'s part of the light is `light`).
    fn pmf(&self, ctx: &LightContext, light: usize) -> f32;

    /// A direction towards `light`, which `sample` picked at `ctx` with probability `pick`,
    /// drawn with `u`; the sample's `pdf` is the joint density of the pick and the direction.
    /// By default the light draws its own direction; a sampler that learned where light comes
    /// from at `ctx` may draw it instead.
    fn sample_li(
        &self,
        scene: &Scene,
        lights: &Lights,
        ctx: &LightContext,
        (light, pick): (usize, f32),
        u: Vec2,
    ) -> Option<LightSample> {
        Some(
            lights.lights[light]
                .sample_li(scene, ctx.p, u)?
                .picked(pick),
        )
    }

    /// The joint density with which `sample` and then [`LightSampler::sample_li`] at `ctx`
    /// pick `light` and give the direction `wi` that meets it at `hit`.
    fn pdf_li(
        &self,
        scene: &Scene,
        lights: &Lights,
        ctx: &LightContext,
        light: usize,
        wi: Vec3,
        hit: LightHit,
    ) -> f32 {
        self.pmf(ctx, light) * lights.lights[light].pdf_li(scene, ctx.p, wi, hit)
    }

    /// The lights one next-event estimate takes at `ctx`: each pick stands for its own part
    /// of the lights (disjoint), and their estimates add. One pick by `sample` unless the
    /// sampler splits.
    fn sample_all(&self, ctx: &LightContext, u: f32, picks: &mut Picks) {
        if let Some(pick) = self.sample(ctx, u) {
            picks.push(pick);
        }
    }

    /// Whether the sampler learns from the light samples of pass `pass` (a learned sampler;
    /// the fixed ones learn nothing).
    fn learns(&self, _pass: u32) -> bool {
        false
    }

    /// Learns from the light samples of a pass it asked for, every block's in block order;
    /// what it learns applies from the next pass on.
    fn learn(&self, _blocks: &[LightRecords]) {}

    /// What a sampler that chooses its strategy when built chose, for the log, and the
    /// measured efficiency of splitting the lights at infinity over one pick by power (see
    /// [`super::AutoLightSampler`]); `None` for the samplers that choose nothing.
    fn choice(&self) -> Option<(String, f64)> {
        None
    }
}

/// Most lights one next-event estimate picks.
pub const MAX_PICKS: usize = 8;

/// The lights picked for one next-event estimate, with their probabilities.
#[derive(Clone, Copy, Debug, Default)]
pub struct Picks {
    len: usize,
    items: [(usize, f32); MAX_PICKS],
}

impl Picks {
    /// Adds a pick; false (and nothing added) once [`MAX_PICKS`] are there.
    pub fn push(&mut self, pick: (usize, f32)) -> bool {
        if self.len == MAX_PICKS {
            return false;
        }
        self.items[self.len] = pick;
        self.len += 1;
        true
    }

    /// The picks so far.
    pub fn as_slice(&self) -> &[(usize, f32)] {
        &self.items[..self.len]
    }
}

crate::choices! {
    /// The fixed light samplers, by name.
    pub enum LightSelection {
        /// Every light with the same probability.
        Uniform = "uniform",
        /// In proportion to emitted power.
        Power = "power",
        /// Every light in each estimate (split into [`MAX_PICKS`] groups of about equal power
        /// when there are more).
        All = "all",
        /// Each light at infinity in every estimate, one of the other lights by power.
        Split = "split",
        /// Split where a pilot measures that it pays, else power ([`super::AutoLightSampler`]).
        Auto = "auto",
    }
}

crate::options! {
    /// Light sampling (af_hf, lp_hf, sdrc, shrc).
    pub struct LightOptions in "light", flags "light" {
        /// How next-event estimation picks a light: the name of a registered light sampler
        /// (`fenestra list` shows them).
        pub selection: String = LightSelection::Auto.as_str().to_string(),
    }
}

impl crate::options::Validate for LightOptions {}

impl LightSelection {
    /// The sampler for the lights of `render_scene`.
    pub fn build(self, render_scene: &RenderScene) -> Box<dyn LightSampler> {
        let (scene, lights) = (&render_scene.scene, &render_scene.lights);
        match self {
            LightSelection::Uniform => Box::new(UniformLightSampler::new(lights)),
            LightSelection::Power => Box::new(PowerLightSampler::new(scene, lights)),
            LightSelection::All => Box::new(SplitLightSampler::all(scene, lights)),
            LightSelection::Split => Box::new(SplitLightSampler::at_infinity(scene, lights)),
            LightSelection::Auto => Box::new(super::AutoLightSampler::new(render_scene)),
        }
    }
}

/// Every light with the same probability.
pub struct UniformLightSampler {
    count: usize,
}

impl UniformLightSampler {
    /// A sampler over `lights`.
    pub fn new(lights: &Lights) -> Self {
        UniformLightSampler {
            count: lights.lights.len(),
        }
    }
}

impl LightSampler for UniformLightSampler {
    fn sample(&self, _: &LightContext, u: f32) -> Option<(usize, f32)> {
        if self.count == 0 {
            return None;
        }
        let i = ((u * self.count as f32) as usize).min(self.count - 1);
        Some((i, 1.0 / self.count as f32))
    }
    fn pmf(&self, _: &LightContext, light: usize) -> f32 {
        if light < self.count {
            1.0 / self.count as f32
        } else {
            0.0
        }
    }
}

/// Lights chosen in proportion to their emitted power.
pub struct PowerLightSampler {
    distribution: Option<Distribution1D>,
}

impl PowerLightSampler {
    /// A sampler over `lights` of `scene`.
    pub fn new(scene: &Scene, lights: &Lights) -> Self {
        let powers: Vec<f32> = lights.lights.iter().map(|l| l.power(scene)).collect();
        PowerLightSampler {
            distribution: (!powers.is_empty()).then(|| Distribution1D::new(&powers)),
        }
    }
}

impl LightSampler for PowerLightSampler {
    fn sample(&self, _: &LightContext, u: f32) -> Option<(usize, f32)> {
        let d = self.distribution.as_ref()?;
        let (i, pmf, _) = d.sample_discrete(u);
        (pmf > 0.0).then_some((i, pmf))
    }
    fn pmf(&self, _: &LightContext, light: usize) -> f32 {
        self.distribution
            .as_ref()
            .map_or(0.0, |d| d.discrete_pmf(light))
    }
}

/// Lights split into groups, each next-event estimate taking one light of every group (in
/// proportion to its power within the group): splitting, where a single pick would multiply a
/// light's estimate by one over its probability of being picked.
pub struct SplitLightSampler {
    /// Per group: its lights and the power distribution over them.
    groups: Vec<(Vec<usize>, Distribution1D)>,
    /// Per light: its group and its place in the group.
    place: Vec<(usize, usize)>,
}

impl SplitLightSampler {
    /// Every light in each estimate, as pbrt's "uniform sample all lights" direct lighting:
    /// a light sample per light, each with probability 1, where a scene has at most
    /// [`MAX_PICKS`] lights (a few spots and a sky, a sun and a sky). More lights are split,
    /// in index order, into [`MAX_PICKS`] groups of about equal power.
    pub fn all(scene: &Scene, lights: &Lights) -> Self {
        let powers: Vec<f32> = lights.lights.iter().map(|l| l.power(scene)).collect();
        Self::all_of(&powers)
    }

    fn all_of(powers: &[f32]) -> Self {
        let mut start = 0;
        let groups = group_ends(powers, MAX_PICKS)
            .into_iter()
            .map(|end| {
                let group = (start..end).collect();
                start = end;
                group
            })
            .collect();
        Self::from_groups(powers, groups)
    }

    /// Each light at infinity (a sky or environment map, the sun, a distant light) in every
    /// estimate, and one of the other lights by power: on a room lit by a sky and a sun, a
    /// single pick leaves the sunlit patches' direct light a coin toss between the two (at
    /// most [`MAX_PICKS`] - 1 lights at infinity take their own sample; any more, and those
    /// that emit nothing, join the others).
    pub fn at_infinity(scene: &Scene, lights: &Lights) -> Self {
        let powers: Vec<f32> = lights.lights.iter().map(|l| l.power(scene)).collect();
        let infinite: Vec<bool> = lights.lights.iter().map(|l| l.at_infinity()).collect();
        Self::at_infinity_of(&powers, &infinite)
    }

    fn at_infinity_of(powers: &[f32], infinite: &[bool]) -> Self {
        let mut groups: Vec<Vec<usize>> = (0..powers.len())
            .filter(|&i| infinite[i] && powers[i] > 0.0)
            .take(MAX_PICKS - 1)
            .map(|i| vec![i])
            .collect();
        let taken: Vec<usize> = groups.iter().flatten().copied().collect();
        let rest: Vec<usize> = (0..powers.len()).filter(|i| !taken.contains(i)).collect();
        if !rest.is_empty() {
            groups.push(rest);
        }
        Self::from_groups(powers, groups)
    }

    /// A sampler over lights of these powers, split into `groups` (disjoint, non-empty,
    /// covering every light).
    fn from_groups(powers: &[f32], groups: Vec<Vec<usize>>) -> Self {
        let mut place = vec![(0, 0); powers.len()];
        let groups = groups
            .into_iter()
            .enumerate()
            .map(|(g, lights)| {
                for (k, &i) in lights.iter().enumerate() {
                    place[i] = (g, k);
                }
                // A group of dark lights is sampled uniformly (Distribution1D's rule for zero
                // sums).
                let group_powers: Vec<f32> = lights.iter().map(|&i| powers[i]).collect();
                (lights, Distribution1D::new(&group_powers))
            })
            .collect();
        SplitLightSampler { groups, place }
    }

    /// How many lights an estimate takes.
    pub fn picks(&self) -> usize {
        self.groups.len()
    }
}

/// Ends of at most `count` consecutive non-empty groups of `powers` of about equal power:
/// every light its own group when there are at most `count`.
fn group_ends(powers: &[f32], count: usize) -> Vec<usize> {
    let n = powers.len();
    if n <= count {
        return (1..=n).collect();
    }
    let total: f64 = powers.iter().map(|&p| p as f64).sum();
    let mut ends = Vec::with_capacity(count);
    let mut sum = 0.0f64;
    for (i, &p) in powers.iter().enumerate() {
        sum += p as f64;
        let groups_left = count - ends.len();
        // Close the group once it holds its share, leaving a light for each later group.
        let share = total * (ends.len() + 1) as f64 / count as f64;
        if groups_left > 1 && (sum >= share || n - (i + 1) < groups_left) {
            ends.push(i + 1);
        }
    }
    ends.push(n);
    ends
}

impl LightSampler for SplitLightSampler {
    /// One pick alone: a group uniformly, then a light of it by power (with its probability
    /// of that; `pmf` gives the splitting estimate's, so one-pick mixtures refuse this sampler).
    fn sample(&self, _: &LightContext, u: f32) -> Option<(usize, f32)> {
        let n = self.groups.len();
        let g = ((u * n as f32) as usize).min(n.checked_sub(1)?);
        let (lights, d) = &self.groups[g];
        let (i, pmf, _) = d.sample_discrete(u * n as f32 - g as f32);
        (pmf > 0.0).then_some((lights[i], pmf / n as f32))
    }

    fn pmf(&self, _: &LightContext, light: usize) -> f32 {
        self.place
            .get(light)
            .map_or(0.0, |&(g, k)| self.groups[g].1.discrete_pmf(k))
    }

    fn sample_all(&self, _: &LightContext, u: f32, picks: &mut Picks) {
        for (lights, d) in &self.groups {
            let (i, pmf, _) = d.sample_discrete(u);
            if pmf > 0.0 {
                picks.push((lights[i], pmf));
            }
        }
    }
}

/// The suns (compact lights at infinity: a sun's disk, a distant light) each taken in every
/// estimate, and `inner`'s picks standing for the other lights: where `inner` picks a sun the
/// pick is dropped, so the other lights keep `inner`'s probabilities and their estimate stays
/// unbiased. For a learned sampler, which then learns only what its own picks find
/// (the sky's regions, the lamps), while a sunlit patch's direct sun is no coin toss.
pub struct SplitSuns {
    inner: Box<dyn LightSampler>,
    /// Per light: whether it is a sun.
    is_sun: Vec<bool>,
    /// The suns (not a scan of `is_sun` per estimate: a building has thousands of lights).
    suns: Vec<usize>,
}

impl SplitSuns {
    /// `inner` over `lights`, with the suns taken apart.
    pub fn new(inner: Box<dyn LightSampler>, lights: &Lights) -> Self {
        let is_sun = lights
            .lights
            .iter()
            .map(|l| l.at_infinity() && l.is_compact())
            .collect();
        Self::with_suns(inner, is_sun)
    }

    /// `inner` with the lights that `is_sun` marks taken apart.
    fn with_suns(inner: Box<dyn LightSampler>, is_sun: Vec<bool>) -> Self {
        let suns = (0..is_sun.len()).filter(|&l| is_sun[l]).collect();
        SplitSuns {
            inner,
            is_sun,
            suns,
        }
    }

    /// The sampler of the other lights.
    pub fn inner(&self) -> &dyn LightSampler {
        self.inner.as_ref()
    }

    /// The sampler of the other lights, unwrapped.
    pub fn into_inner(self) -> Box<dyn LightSampler> {
        self.inner
    }

    fn is_sun(&self, light: usize) -> bool {
        self.is_sun.get(light).copied().unwrap_or(false)
    }
}

impl LightSampler for SplitSuns {
    /// One pick alone (`inner`'s, a sun among them; `pmf` gives the splitting estimate's, so
    /// one-pick mixtures refuse this sampler).
    fn sample(&self, ctx: &LightContext, u: f32) -> Option<(usize, f32)> {
        self.inner.sample(ctx, u)
    }

    fn pmf(&self, ctx: &LightContext, light: usize) -> f32 {
        if self.is_sun(light) {
            1.0
        } else {
            self.inner.pmf(ctx, light)
        }
    }

    fn sample_li(
        &self,
        scene: &Scene,
        lights: &Lights,
        ctx: &LightContext,
        (light, pick): (usize, f32),
        u: Vec2,
    ) -> Option<LightSample> {
        if self.is_sun(light) {
            Some(
                lights.lights[light]
                    .sample_li(scene, ctx.p, u)?
                    .picked(pick),
            )
        } else {
            self.inner.sample_li(scene, lights, ctx, (light, pick), u)
        }
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
        if self.is_sun(light) {
            lights.lights[light].pdf_li(scene, ctx.p, wi, hit)
        } else {
            self.inner.pdf_li(scene, lights, ctx, light, wi, hit)
        }
    }

    fn sample_all(&self, ctx: &LightContext, u: f32, picks: &mut Picks) {
        for &sun in &self.suns {
            picks.push((sun, 1.0));
        }
        let mut inner = Picks::default();
        self.inner.sample_all(ctx, u, &mut inner);
        for &pick in inner.as_slice().iter().filter(|p| !self.is_sun(p.0)) {
            picks.push(pick);
        }
    }

    fn learns(&self, pass: u32) -> bool {
        self.inner.learns(pass)
    }

    /// `inner` learns from its own picks' samples: the suns' are left out.
    fn learn(&self, blocks: &[LightRecords]) {
        let own: Vec<LightRecords> = blocks
            .iter()
            .map(|b| b.retained(|r| !self.is_sun(r.light as usize)))
            .collect();
        self.inner.learn(&own);
    }

    fn choice(&self) -> Option<(String, f64)> {
        self.inner.choice()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_pick_and_the_splitting_picks_have_the_probabilities_they_claim() {
        let mut rng = fenestra_core::Rng::new(8);
        let sample = SampleContext::SINGLE;
        let ctx = LightContext {
            p: Vec3::ZERO,
            n: Vec3::Z,
            sample: &sample,
        };
        for n in [5, 30] {
            let powers: Vec<f32> = (0..n).map(|_| rng.next_f32() + 0.01).collect();
            let all = SplitLightSampler::all_of(&powers);
            // u on a fine stratified grid: each light's share of the picks is its probability.
            let draws = 100_000;
            let (mut one, mut split) = (vec![0.0f64; n], vec![0.0f64; n]);
            for k in 0..draws {
                let u = (k as f32 + 0.5) / draws as f32;
                let (i, p) = all.sample(&ctx, u).expect("a pick");
                assert!((p - all.pmf(&ctx, i) / all.groups.len() as f32).abs() < 1e-6);
                one[i] += 1.0 / draws as f64;
                let mut picks = Picks::default();
                all.sample_all(&ctx, u, &mut picks);
                for &(i, p) in picks.as_slice() {
                    assert_eq!(p, all.pmf(&ctx, i));
                    split[i] += 1.0 / draws as f64;
                }
            }
            for i in 0..n {
                let pmf = all.pmf(&ctx, i) as f64;
                assert!(
                    (split[i] - pmf).abs() < 1e-3,
                    "{n} lights, light {i}: {split:?}"
                );
                let share = pmf / all.groups.len() as f64;
                assert!(
                    (one[i] - share).abs() < 1e-3,
                    "{n} lights, light {i}: {one:?}"
                );
            }
        }
    }

    #[test]
    fn each_light_at_infinity_is_picked_in_every_estimate_and_one_other_by_power() {
        let sample = SampleContext::SINGLE;
        let ctx = LightContext {
            p: Vec3::ZERO,
            n: Vec3::Z,
            sample: &sample,
        };
        // A sky, two lamps, a sun, a dark distant light, a third lamp.
        let powers = [50.0, 1.0, 3.0, 200.0, 0.0, 4.0];
        let infinite = [true, false, false, true, true, false];
        let split = SplitLightSampler::at_infinity_of(&powers, &infinite);
        assert_eq!(split.picks(), 3);
        // The lamps and the dark light share one pick, by power (1 + 3 + 0 + 4).
        let expected = |i: usize| match i {
            0 | 3 => 1.0,
            _ => powers[i] / 8.0,
        };
        let expected: Vec<f32> = (0..6).map(expected).collect();
        assert_picks_follow(&split, &ctx, &expected, |_| {});
        // No light at infinity: one light by power, as power selection.
        let lamps_only = SplitLightSampler::at_infinity_of(&powers, &[false; 6]);
        assert_eq!(lamps_only.picks(), 1);
    }

    /// Each light's share of `sampler`'s estimates over a fine stratified grid of u is its
    /// `expected` probability, which `pmf` claims, as does every pick; `each` checks each
    /// estimate's picks.
    fn assert_picks_follow(
        sampler: &dyn LightSampler,
        ctx: &LightContext,
        expected: &[f32],
        each: impl Fn(&Picks),
    ) {
        let draws = 80_000;
        let mut counts = vec![0.0f64; expected.len()];
        for k in 0..draws {
            let u = (k as f32 + 0.5) / draws as f32;
            let mut picks = Picks::default();
            sampler.sample_all(ctx, u, &mut picks);
            each(&picks);
            for &(i, p) in picks.as_slice() {
                assert_eq!(p, sampler.pmf(ctx, i), "light {i}");
                counts[i] += 1.0 / draws as f64;
            }
        }
        for (i, &e) in expected.iter().enumerate() {
            assert!((sampler.pmf(ctx, i) - e).abs() < 1e-6, "light {i}");
            assert!((counts[i] - e as f64).abs() < 1e-3, "light {i}: {counts:?}");
        }
    }

    /// A sampler that picks by power over every light and keeps the lights it learned from.
    struct Spy {
        power: PowerLightSampler,
        learned: std::sync::Arc<std::sync::Mutex<Vec<u32>>>,
    }

    impl LightSampler for Spy {
        fn sample(&self, ctx: &LightContext, u: f32) -> Option<(usize, f32)> {
            self.power.sample(ctx, u)
        }
        fn pmf(&self, ctx: &LightContext, light: usize) -> f32 {
            self.power.pmf(ctx, light)
        }
        fn learn(&self, blocks: &[LightRecords]) {
            let mut learned = self.learned.lock().expect("spy");
            learned.extend(
                blocks
                    .iter()
                    .flat_map(|b| b.records.iter().map(|r| r.light)),
            );
        }
    }

    #[test]
    fn the_suns_are_taken_in_every_estimate_and_the_inner_pick_stands_for_the_rest() {
        let sample = SampleContext::SINGLE;
        let ctx = LightContext {
            p: Vec3::ZERO,
            n: Vec3::Z,
            sample: &sample,
        };
        // A sky, a lamp, a sun, a second lamp: the inner sampler picks among all four by power.
        let powers = [50.0, 10.0, 200.0, 40.0];
        let learned = std::sync::Arc::default();
        let split = SplitSuns::with_suns(
            Box::new(Spy {
                power: PowerLightSampler {
                    distribution: Some(Distribution1D::new(&powers)),
                },
                learned: std::sync::Arc::clone(&learned),
            }),
            vec![false, false, true, false],
        );
        // The sun always; the others as often as the inner sampler picks them (its picks of
        // the sun dropped), each pick with the probability `pmf` claims.
        let total: f32 = powers.iter().sum();
        let expected: Vec<f32> = (0..4)
            .map(|i| if i == 2 { 1.0 } else { powers[i] / total })
            .collect();
        assert_picks_follow(&split, &ctx, &expected, |picks| {
            assert_eq!(picks.as_slice()[0], (2, 1.0), "the sun comes first, always");
        });
        // The inner sampler learns from its own picks' samples, not from the sun's.
        let mut block = LightRecords::new(1.0);
        for light in [0, 2, 1, 2, 3] {
            block.push(super::super::LightRecord {
                p: Vec3::ZERO,
                n: Vec3::Z,
                light,
                wi: Vec3::Z,
                weight: 1.0,
            });
        }
        split.learn(&[block]);
        assert_eq!(*learned.lock().expect("spy"), vec![0, 1, 3]);
    }

    #[test]
    fn groups_cover_the_lights_in_order_with_about_equal_power() {
        assert_eq!(group_ends(&[1.0, 5.0, 2.0], 8), vec![1, 2, 3]);
        assert_eq!(group_ends(&[], 8), Vec::<usize>::new());
        let mut rng = fenestra_core::Rng::new(3);
        for n in [9, 10, 17, 72, 500] {
            let powers: Vec<f32> = (0..n).map(|_| rng.next_f32().powi(3) * 10.0).collect();
            let ends = group_ends(&powers, 8);
            assert_eq!(ends.len(), 8, "{n} lights");
            assert_eq!(ends.last(), Some(&n));
            let total: f32 = powers.iter().sum();
            let largest = powers.iter().copied().fold(0.0, f32::max);
            let mut start = 0;
            for &end in &ends {
                assert!(end > start, "groups are not empty: {ends:?}");
                let power: f32 = powers[start..end].iter().sum();
                // A group closes at the first light that takes it past its share.
                assert!(power <= total / 8.0 + largest + 1e-3, "{n}: {ends:?}");
                start = end;
            }
        }
    }
}
