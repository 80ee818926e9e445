//! Choosing which light to sample at a shading point. An integrator owns its light sampler;
//! learned samplers (seed 004's adaptive cuts, light trees) implement the same trait and see
//! the shading point's pixel, block and pass through [`LightContext`].

use super::{LightRecords, Lights};
use crate::driver::SampleContext;
use fenestra_core::distribution::Distribution1D;
use fenestra_core::{UnknownName, Vec3};
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

/// The fixed light samplers, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightSelection {
    /// Every light with the same probability.
    Uniform,
    /// In proportion to emitted power.
    Power,
}

impl std::str::FromStr for LightSelection {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, UnknownName> {
        match s {
            "uniform" => Ok(LightSelection::Uniform),
            "power" => Ok(LightSelection::Power),
            _ => Err(UnknownName::new("light selection", s, "uniform or power")),
        }
    }
}

impl LightSelection {
    /// The name `--light-selection` takes.
    pub fn name(self) -> &'static str {
        match self {
            LightSelection::Uniform => "uniform",
            LightSelection::Power => "power",
        }
    }

    /// The sampler for `lights` of `scene`.
    pub fn build(self, scene: &Scene, lights: &Lights) -> Box<dyn LightSampler> {
        match self {
            LightSelection::Uniform => Box::new(UniformLightSampler::new(lights)),
            LightSelection::Power => Box::new(PowerLightSampler::new(scene, lights)),
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
