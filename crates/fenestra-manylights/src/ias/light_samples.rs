//! A light sample at a point (seed 004 §3.5): a cluster of its cut drawn from the pass's
//! PDF, a light inside it by power (or a direction of a sky region), and the shadow ray;
//! and the seed's reference PDF over a point's lights (§4.2).

use super::block::{BlockRender, Far};
use super::bsdf_samples;
use super::point::{Point, Shade};
use fenestra_core::stats::RayCounters;
use fenestra_core::{Rgb, Sampler, Vec3};
use fenestra_render::integrator::Sides;
use fenestra_render::light::{LightHit, LightSample};

impl BlockRender<'_> {
    /// The reference's PDF over a point's lights (§4.2): in proportion to each light's
    /// unoccluded irradiance bound at the point; lights at infinity, whose irradiance the
    /// bounds do not give, share the probability of one more light with the rest.
    pub(super) fn irradiance_pdf(&self, q: &Point) -> Vec<f32> {
        let forest = self.forest;
        let first = &q.hits[0];
        let n = if first.bsdf.is_transmissive() {
            Vec3::ZERO
        } else {
            q.n
        };
        let mut w: Vec<f64> = q
            .cut
            .iter()
            .map(|&c| match forest.nodes.get(c as usize) {
                Some(node) => f64::from(node.bounds.importance(first.si.p, n)),
                None => 0.0,
            })
            .collect();
        let finite: f64 = w.iter().sum();
        let infinite = q
            .cut
            .iter()
            .filter(|&&c| c as usize >= forest.nodes.len())
            .count();
        let share = match (infinite, finite > 0.0) {
            (0, _) => 0.0,
            (k, true) => 1.0 / (k + 1) as f64,
            (_, false) => 1.0,
        };
        for (wi, &c) in w.iter_mut().zip(&q.cut) {
            *wi = if c as usize >= forest.nodes.len() {
                share / infinite as f64
            } else if finite > 0.0 {
                *wi / finite * (1.0 - share)
            } else {
                0.0
            };
        }
        w.into_iter().map(|v| v as f32).collect()
    }

    /// One light sample at point `q`, shaded at its hit `at`.
    pub(super) fn sample(
        &self,
        q: &Point,
        at: &Shade,
        pdf: &[f32],
        cdf: &[f32],
        sampler: &mut Sampler,
        rays: &mut RayCounters,
    ) -> LightEval {
        let total = *cdf.last().unwrap_or(&0.0);
        let u = sampler.next_1d() * total;
        let i = cdf.partition_point(|&c| c <= u).min(cdf.len() - 1);
        let p_cluster = pdf[i] / total;
        let node = q.cut[i];
        let forest = self.forest;
        let u_light = sampler.next_1d();
        let (leaf, target, p_light, power) = if (node as usize) < forest.nodes.len() {
            let (leaf, p) = forest.pick_by_power(node, u_light);
            let c = &forest.nodes[leaf as usize];
            (leaf, Far::Light(c.light as usize), p, c.power)
        } else {
            (node, self.far[node as usize - forest.nodes.len()], 1.0, 1.0)
        };
        let mut eval = LightEval {
            value: Rgb::ZERO,
            visible: false,
            leaf,
            contribution: 0.0,
            power,
            wi: Vec3::ZERO,
            density: 0.0,
        };
        let scene = self.scene;
        let s = match target {
            Far::Light(l) => {
                scene.lights.lights[l].sample_li(&scene.scene, at.si.p, sampler.next_2d())
            }
            // A direction uniform in solid angle over the region (§3.5.1's environment
            // regions).
            Far::Region(r) => {
                let wi = r.sample(sampler.next_2d());
                let li = scene.lights.lights[r.light].le(LightHit::Escaped, wi);
                Some(LightSample {
                    wi,
                    li,
                    pdf: 1.0 / r.solid_angle(),
                    point: None,
                    delta: false,
                })
            }
        };
        let Some(s) = s else {
            return eval;
        };
        let frame = at.si.shading_frame();
        let (wo, wi) = (frame.to_local(at.wo), frame.to_local(s.wi));
        // Shading normals must not leak light through the surface.
        if self.sides == Sides::Both
            && !at.bsdf.is_transmissive()
            && (s.wi.dot(q.n) > 0.0) != (wi.z * wo.z > 0.0)
        {
            return eval;
        }
        let unoccluded = at.bsdf.eval(wo, wi) * wi.z.abs() * s.li / s.pdf;
        if unoccluded.is_black() || !unoccluded.is_finite() {
            return eval;
        }
        let (ray, tmax) = at.si.shadow_ray(s.wi, s.point);
        rays.shadow += 1;
        let seen = unoccluded * scene.transmittance(ray, tmax);
        eval.visible = !seen.is_black();
        eval.contribution = f64::from(seen.luminance());
        eval.wi = s.wi;
        eval.density = if s.delta {
            0.0
        } else {
            p_cluster * p_light * s.pdf
        };
        // Weighed against the point's BSDF samples, if it takes them; the statistics learn
        // the whole contribution.
        let weight = if q.lookup.is_empty() || s.delta {
            1.0
        } else {
            bsdf_samples::HEURISTIC.weight(eval.density, at.bsdf.pdf(wo, wi))
        };
        eval.value = seen * (weight / (p_cluster * p_light));
        eval
    }
}

/// What one light sample gives.
pub(super) struct LightEval {
    /// Its contribution over its probability (the point's estimator).
    pub(super) value: Rgb,
    /// Whether the shadow ray reached the light.
    pub(super) visible: bool,
    /// The light's node (for the statistics).
    pub(super) leaf: u32,
    /// The light's own contribution estimate (luminance, occlusion included).
    pub(super) contribution: f64,
    /// The light's power.
    pub(super) power: f32,
    /// The sampled direction and the light technique's solid-angle density of it (0 for a
    /// Dirac light).
    pub(super) wi: Vec3,
    pub(super) density: f32,
}
