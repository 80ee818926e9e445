//! Unidirectional path tracing with Russian roulette (seed 000 §3.2.1), in two flavours:
//! `hf` samples the BSDF only (seed 000's hemispherical formulation); `af_hf` adds next-event
//! estimation on emitters and combines both techniques by MIS (seed 000 §4, §5.2).

use super::{
    render_progressive, Integrator, IntegratorOptions, PathEstimator, RenderControl, RenderSettings,
};
use crate::film::Film;
use crate::light::Light;
use crate::stats::{RayCounters, RenderStats};
use crate::RenderScene;
use fenestra_core::ray::offset_origin;
use fenestra_core::{Ray, Rgb, Sampler, Vec3};
use fenestra_scene::SurfaceInteraction;

pub struct PathTracer {
    nee: bool,
    options: IntegratorOptions,
}

impl PathTracer {
    pub fn new(nee: bool, options: IntegratorOptions) -> Self {
        PathTracer { nee, options }
    }
}

impl Integrator for PathTracer {
    fn name(&self) -> String {
        if self.nee { "af_hf" } else { "hf" }.to_string()
    }

    fn max_depth(&self) -> u32 {
        self.options.max_depth
    }

    fn render(
        &self,
        scene: &RenderScene,
        film: &mut Film,
        settings: &RenderSettings,
        control: &RenderControl,
    ) -> RenderStats {
        render_progressive(
            &self.name(),
            self.options.max_depth,
            self,
            scene,
            film,
            settings,
            control,
        )
    }
}

/// Whether `wi` and `wo` lie on the sides of the geometric surface that the local (shading)
/// directions claim: guards against light leaks through shading normals.
fn sides_agree(si: &SurfaceInteraction, wo: Vec3, wi: Vec3, wo_z: f32, wi_z: f32) -> bool {
    (wi.dot(si.ng) * wo.dot(si.ng) > 0.0) == (wi_z * wo_z > 0.0)
}

/// The state of the previous vertex that MIS needs when a BSDF-sampled ray finds an emitter.
struct Previous {
    p: Vec3,
    n: Vec3,
    bsdf_pdf: f32,
    delta: bool,
}

impl PathTracer {
    /// MIS weight of the BSDF technique for an emitter found by a BSDF-sampled ray whose
    /// light-sampling density (light pick probability times solid-angle density) is `light_pdf`.
    fn bsdf_weight(&self, prev: &Previous, light_pdf: impl FnOnce() -> f32) -> f32 {
        if !self.nee || prev.delta {
            1.0
        } else {
            self.options.mis.weight(prev.bsdf_pdf, light_pdf())
        }
    }

    /// Next-event estimation at `si`: one light sample, weighted by MIS against the BSDF.
    #[allow(clippy::too_many_arguments)]
    fn sample_light(
        &self,
        scene: &RenderScene,
        si: &SurfaceInteraction,
        bsdf: &crate::bsdf::Bsdf,
        wo: Vec3,
        wo_local: Vec3,
        sampler: &mut Sampler,
        rays: &mut RayCounters,
    ) -> Rgb {
        let u_pick = sampler.next_1d();
        let u = sampler.next_2d();
        let Some((index, pick)) = scene.light_sampler.sample(si.p, si.ns, u_pick) else {
            return Rgb::ZERO;
        };
        let Some(ls) = scene.lights.lights[index].sample_li(&scene.scene, si.p, u) else {
            return Rgb::ZERO;
        };
        let frame = si.shading_frame();
        let wi_local = frame.to_local(ls.wi);
        if !sides_agree(si, wo, ls.wi, wo_local.z, wi_local.z) {
            return Rgb::ZERO;
        }
        let f = bsdf.eval(wo_local, wi_local);
        if f.is_black() {
            return Rgb::ZERO;
        }
        let origin = offset_origin(si.p, si.ng, ls.wi);
        let tmax = ls
            .point
            .map_or(f32::INFINITY, |q| (q - origin).length() * (1.0 - 1e-4));
        rays.shadow += 1;
        if scene.scene.occluded(&Ray::new(origin, ls.wi), tmax) {
            return Rgb::ZERO;
        }
        let light_pdf = pick * ls.pdf;
        let weight = if ls.delta {
            1.0
        } else {
            self.options
                .mis
                .weight(light_pdf, bsdf.pdf(wo_local, wi_local))
        };
        f * ls.li * (wi_local.z.abs() * weight / light_pdf)
    }
}

impl PathEstimator for PathTracer {
    fn li(
        &self,
        scene: &RenderScene,
        mut ray: Ray,
        sampler: &mut Sampler,
        rays: &mut RayCounters,
    ) -> Rgb {
        let max_depth = self.options.max_depth;
        let mut l = Rgb::ZERO;
        let mut beta = Rgb::ONE;
        let mut prev = Previous {
            p: ray.o,
            n: ray.d,
            bsdf_pdf: 0.0,
            delta: true,
        };
        // `segments` counts the path's segments up to the vertex being shaded.
        for segments in 1.. {
            if segments > 1 {
                rays.bounce += 1;
            }
            let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
                for &e in &scene.lights.environments {
                    let Light::Environment(env) = &scene.lights.lights[e] else {
                        continue;
                    };
                    let w = self.bsdf_weight(&prev, || {
                        scene.light_sampler.pmf(prev.p, prev.n, e) * env.pdf_li(ray.d)
                    });
                    l += beta * env.le(ray.d) * w;
                }
                break;
            };
            let si = scene.scene.interaction(&ray, &hit);
            let wo = -ray.d;
            if let Some((index, le)) = scene.lights.le(&si, wo) {
                if !le.is_black() {
                    let w = self.bsdf_weight(&prev, || {
                        let Light::Area(area) = &scene.lights.lights[index] else {
                            return 0.0;
                        };
                        scene.light_sampler.pmf(prev.p, prev.n, index)
                            * area.pdf_li(&scene.scene, prev.p, &si)
                    });
                    l += beta * le * w;
                }
            }
            if segments >= max_depth {
                break;
            }
            let bsdf = scene.bsdf_at(&si);
            let bsdf = bsdf.as_ref();
            let frame = si.shading_frame();
            let wo_local = frame.to_local(wo);
            if self.nee && !bsdf.is_delta() {
                l += beta * self.sample_light(scene, &si, bsdf, wo, wo_local, sampler, rays);
            }
            let uc = sampler.next_1d();
            let u = sampler.next_2d();
            let Some(bs) = bsdf.sample(wo_local, uc, u) else {
                break;
            };
            let wi = frame.to_world(bs.wi);
            if !sides_agree(&si, wo, wi, wo_local.z, bs.wi.z) {
                break;
            }
            beta *= bs.weight;
            prev = Previous {
                p: si.p,
                n: si.ns,
                bsdf_pdf: bs.pdf,
                delta: bs.delta,
            };
            if segments + 1 >= self.options.rr_depth {
                // Russian roulette (seed 000 §3.2.1): continue with probability q, divide by q.
                let q = beta.max_component().min(0.95);
                if q <= 0.0 || sampler.next_1d() >= q {
                    break;
                }
                beta *= 1.0 / q;
            }
            ray = Ray::new(offset_origin(si.p, si.ng, wi), wi);
        }
        l
    }
}
