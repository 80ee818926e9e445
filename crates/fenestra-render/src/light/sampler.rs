//! Choosing which light to sample at a shading point. Later samplers (irradiance-based,
//! light BVH, seed 004's adaptive cuts) implement the same trait.

use super::Lights;
use fenestra_core::distribution::Distribution1D;
use fenestra_core::Vec3;
use fenestra_scene::Scene;

pub trait LightSampler: Send + Sync {
    /// Picks a light for point `p` with shading normal `n`: (light index, probability).
    fn sample(&self, p: Vec3, n: Vec3, u: f32) -> Option<(usize, f32)>;
    /// Probability that `sample` picks `light` at `p`.
    fn pmf(&self, p: Vec3, n: Vec3, light: usize) -> f32;
}

/// Every light with the same probability.
pub struct UniformLightSampler {
    count: usize,
}

impl UniformLightSampler {
    pub fn new(lights: &Lights) -> Self {
        UniformLightSampler {
            count: lights.lights.len(),
        }
    }
}

impl LightSampler for UniformLightSampler {
    fn sample(&self, _p: Vec3, _n: Vec3, u: f32) -> Option<(usize, f32)> {
        if self.count == 0 {
            return None;
        }
        let i = ((u * self.count as f32) as usize).min(self.count - 1);
        Some((i, 1.0 / self.count as f32))
    }
    fn pmf(&self, _p: Vec3, _n: Vec3, light: usize) -> f32 {
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
    pub fn new(scene: &Scene, lights: &Lights) -> Self {
        let powers: Vec<f32> = lights.lights.iter().map(|l| l.power(scene)).collect();
        PowerLightSampler {
            distribution: (!powers.is_empty()).then(|| Distribution1D::new(&powers)),
        }
    }
}

impl LightSampler for PowerLightSampler {
    fn sample(&self, _p: Vec3, _n: Vec3, u: f32) -> Option<(usize, f32)> {
        let d = self.distribution.as_ref()?;
        let (i, pmf, _) = d.sample_discrete(u);
        (pmf > 0.0).then_some((i, pmf))
    }
    fn pmf(&self, _p: Vec3, _n: Vec3, light: usize) -> f32 {
        self.distribution
            .as_ref()
            .map_or(0.0, |d| d.discrete_pmf(light))
    }
}
