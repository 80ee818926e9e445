//! Unidirectional path tracing with Russian roulette (seed 000 §3.2.1), in three flavours:
//! `hf` samples the BSDF only (seed 000's hemispherical formulation); `af_hf` adds next-event
//! estimation on emitters and combines both techniques by MIS (seed 000 §4, §5.2); `lp_hf`
//! samples directions through light portals instead (eq. 4.1) and finds what lies beyond
//! (an emitter or the environment), combined with BSDF sampling by MIS; delta lights, which
//! BSDF sampling cannot hit, keep their own next-event estimation.

use super::{
    render_progressive, Integrator, IntegratorOptions, PathEstimator, RenderControl, RenderSettings,
};
use crate::bsdf::Bsdf;
use crate::film::Film;
use crate::light::Light;
use crate::portal::{Portals, Side};
use crate::stats::{RayCounters, RenderStats};
use crate::RenderScene;
use fenestra_core::ray::offset_origin;
use fenestra_core::{Ray, Rgb, Sampler, Vec3};
use fenestra_scene::SurfaceInteraction;

/// Consecutive panes a path may pass straight through (as for shadow rays).
const MAX_PANES: u32 = 16;

/// How directions towards light are chosen besides BSDF sampling.
pub enum NextEvent {
    /// None: BSDF sampling only (hf).
    Off,
    /// Emitters, picked by the scene's light sampler (af_hf).
    Lights,
    /// Light portals (lp_hf); with probability `light_mix` a sample comes from the light
    /// sampler instead (one-sample mixture, as Cycles mixes portals with environment
    /// sampling).
    Portals { portals: Portals, light_mix: f32 },
}

pub struct PathTracer {
    next_event: NextEvent,
    options: IntegratorOptions,
}

impl PathTracer {
    pub fn new(nee: bool, options: IntegratorOptions) -> Self {
        let next_event = if nee {
            NextEvent::Lights
        } else {
            NextEvent::Off
        };
        PathTracer {
            next_event,
            options,
        }
    }

    /// lp_hf: portal sampling (mixed with light sampling with probability `light_mix`) and
    /// BSDF sampling combined by MIS.
    pub fn with_portals(portals: Portals, light_mix: f32, options: IntegratorOptions) -> Self {
        PathTracer {
            next_event: NextEvent::Portals {
                portals,
                light_mix: light_mix.clamp(0.0, 1.0),
            },
            options,
        }
    }
}

impl Integrator for PathTracer {
    fn name(&self) -> String {
        match self.next_event {
            NextEvent::Off => "hf",
            NextEvent::Lights => "af_hf",
            NextEvent::Portals { .. } => "lp_hf",
        }
        .to_string()
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

/// The BSDF at `si` for light arriving from `wi` (world): the local direction and f, or
/// `None` when the sides disagree or f vanishes.
fn bsdf_toward(
    si: &SurfaceInteraction,
    bsdf: &crate::bsdf::Bsdf,
    wo: Vec3,
    wo_local: Vec3,
    wi: Vec3,
) -> Option<(Vec3, Rgb)> {
    let wi_local = si.shading_frame().to_local(wi);
    if !sides_agree(si, wo, wi, wo_local.z, wi_local.z) {
        return None;
    }
    let f = bsdf.eval(wo_local, wi_local);
    (!f.is_black()).then_some((wi_local, f))
}

/// Light reaches an opaque surface from the side `wo` leaves on; a transmissive one from
/// both.
fn side(si: &SurfaceInteraction, bsdf: &Bsdf, wo: Vec3) -> Side {
    (!bsdf.is_transmissive()).then(|| si.ng * si.ng.dot(wo).signum())
}

/// The state of the previous vertex that MIS needs when a BSDF-sampled ray finds an emitter.
struct Previous {
    p: Vec3,
    n: Vec3,
    /// Which way light may arrive, and the portals' total pick weight there (lp_hf).
    side: Side,
    portal_total: f32,
    bsdf_pdf: f32,
    delta: bool,
}

impl PathTracer {
    /// MIS weight of the BSDF technique for light found by a BSDF-sampled ray leaving the
    /// previous vertex along `d`; `light_pdf` is the emitter technique's density (light pick
    /// probability times solid-angle density) for af_hf. For lp_hf the portal density of `d`
    /// counts, whatever the ray found beyond, mixed with `light_pdf` by `light_mix`.
    fn bsdf_weight(&self, prev: &Previous, d: Vec3, light_pdf: impl FnOnce() -> f32) -> f32 {
        if prev.delta {
            return 1.0;
        }
        match &self.next_event {
            NextEvent::Off => 1.0,
            NextEvent::Lights => self.options.mis.weight(prev.bsdf_pdf, light_pdf()),
            NextEvent::Portals { portals, light_mix } => {
                let mut p =
                    (1.0 - light_mix) * portals.pdf(prev.p, prev.side, prev.portal_total, d);
                if *light_mix > 0.0 {
                    p += light_mix * light_pdf();
                }
                self.options.mis.weight(prev.bsdf_pdf, p)
            }
        }
    }

    /// Portal sampling at `si` (eq. 4.1), or with probability `light_mix` light sampling: a
    /// direction, the radiance of whatever the ray meets first beyond thin glass (emitter or
    /// environment), weighted by MIS against the BSDF with the mixture's density.
    #[allow(clippy::too_many_arguments)]
    fn sample_portal(
        &self,
        scene: &RenderScene,
        portals: &Portals,
        light_mix: f32,
        portal_total: f32,
        si: &SurfaceInteraction,
        bsdf: &crate::bsdf::Bsdf,
        wo: Vec3,
        wo_local: Vec3,
        sampler: &mut Sampler,
        rays: &mut RayCounters,
    ) -> Rgb {
        let by_light = light_mix > 0.0 && sampler.next_1d() < light_mix;
        let u_pick = sampler.next_1d();
        let u = sampler.next_2d();
        let side = side(si, bsdf, wo);
        // The light sampled in light mode: only it may be found along the ray (as a shadow
        // ray would have it), so the mixture density counts that light's density alone.
        let (wi, sampled) = if by_light {
            let Some((index, _)) = scene.light_sampler.sample(si.p, si.ns, u_pick) else {
                return Rgb::ZERO;
            };
            match scene.lights.lights[index].sample_li(&scene.scene, si.p, u) {
                // Dirac lights have their own estimator.
                Some(ls) if !ls.delta => (ls.wi, Some(index)),
                _ => return Rgb::ZERO,
            }
        } else {
            let Some(ps) = portals.sample(si.p, side, portal_total, u_pick, u) else {
                return Rgb::ZERO;
            };
            (ps.wi, None)
        };
        let seen = |index: usize| sampled.is_none_or(|s| s == index);
        let Some((wi_local, f)) = bsdf_toward(si, bsdf, wo, wo_local, wi) else {
            return Rgb::ZERO;
        };
        rays.shadow += 1;
        let ray = Ray::new(offset_origin(si.p, si.ng, wi), wi);
        // Radiance found beyond and the light sampler's density of that direction.
        let (li, light_pdf) = match scene.through_glass(ray, f32::INFINITY) {
            (tr, Some(hit)) => {
                let beyond = scene.scene.interaction(&ray, &hit);
                match scene.lights.le(&beyond, -wi) {
                    Some((index, le)) if seen(index) => {
                        let pdf = match &scene.lights.lights[index] {
                            Light::Area(a) if light_mix > 0.0 => {
                                scene.light_sampler.pmf(si.p, si.ns, index)
                                    * a.pdf_li(&scene.scene, si.p, &beyond)
                            }
                            _ => 0.0,
                        };
                        (tr * le, pdf)
                    }
                    _ => (Rgb::ZERO, 0.0),
                }
            }
            (tr, None) => {
                scene
                    .lights
                    .environments
                    .iter()
                    .fold((Rgb::ZERO, 0.0), |(l, pdf), &e| {
                        match &scene.lights.lights[e] {
                            Light::Environment(env) if seen(e) => (
                                l + tr * env.le(wi),
                                pdf + scene.light_sampler.pmf(si.p, si.ns, e) * env.pdf_li(wi),
                            ),
                            _ => (l, pdf),
                        }
                    })
            }
        };
        if li.is_black() {
            return Rgb::ZERO;
        }
        let pdf =
            (1.0 - light_mix) * portals.pdf(si.p, side, portal_total, wi) + light_mix * light_pdf;
        if !(pdf > 0.0) {
            return Rgb::ZERO;
        }
        let weight = self.options.mis.weight(pdf, bsdf.pdf(wo_local, wi_local));
        f * li * (wi_local.z.abs() * weight / pdf)
    }

    /// Next-event estimation at `si`: one light sample, weighted by MIS against the BSDF.
    /// With `delta_only`, only Dirac lights contribute (lp_hf leaves the others to portals
    /// and BSDF sampling); the light pick probability still divides, so the estimate of the
    /// Dirac lights' share stays unbiased.
    #[allow(clippy::too_many_arguments)]
    fn sample_light(
        &self,
        scene: &RenderScene,
        delta_only: bool,
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
        if delta_only && !ls.delta {
            return Rgb::ZERO;
        }
        let Some((wi_local, f)) = bsdf_toward(si, bsdf, wo, wo_local, ls.wi) else {
            return Rgb::ZERO;
        };
        let origin = offset_origin(si.p, si.ng, ls.wi);
        let tmax = ls
            .point
            .map_or(f32::INFINITY, |q| (q - origin).length() * (1.0 - 1e-4));
        rays.shadow += 1;
        let tr = scene.transmittance(Ray::new(origin, ls.wi), tmax);
        if tr.is_black() {
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
        f * ls.li * tr * (wi_local.z.abs() * weight / light_pdf)
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
            side: None,
            portal_total: 0.0,
            bsdf_pdf: 0.0,
            delta: true,
        };
        // `segments` counts the path's segments up to the vertex being shaded; passing
        // straight through a thin pane adds none (shadow and portal rays pass panes too).
        let mut segments = 0;
        let mut panes = 0;
        let mut first = true;
        loop {
            segments += 1;
            if !first {
                rays.bounce += 1;
            }
            first = false;
            let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
                for &e in &scene.lights.environments {
                    let Light::Environment(env) = &scene.lights.lights[e] else {
                        continue;
                    };
                    let w = self.bsdf_weight(&prev, ray.d, || {
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
                    let w = self.bsdf_weight(&prev, ray.d, || {
                        let Light::Area(area) = &scene.lights.lights[index] else {
                            return 0.0;
                        };
                        scene.light_sampler.pmf(prev.p, prev.n, index)
                            * area.pdf_li(&scene.scene, prev.p, &si)
                    });
                    l += beta * le * w;
                }
            }
            let bsdf = scene.bsdf_at(&si);
            let bsdf = bsdf.as_ref();
            let pane = matches!(bsdf, Bsdf::ThinDielectric(_));
            // At the last vertex only a pane's straight-through part may continue the path.
            let at_limit = segments >= max_depth;
            if at_limit && !pane {
                break;
            }
            let frame = si.shading_frame();
            let wo_local = frame.to_local(wo);
            let side = side(&si, bsdf, wo);
            let portal_total = match &self.next_event {
                NextEvent::Portals { portals, .. } if !bsdf.is_delta() => {
                    portals.total_weight(si.p, side)
                }
                _ => 0.0,
            };
            if !bsdf.is_delta() {
                match &self.next_event {
                    NextEvent::Off => {}
                    NextEvent::Lights => {
                        l += beta
                            * self
                                .sample_light(scene, false, &si, bsdf, wo, wo_local, sampler, rays);
                    }
                    NextEvent::Portals { portals, light_mix } => {
                        l += beta
                            * self.sample_portal(
                                scene,
                                portals,
                                *light_mix,
                                portal_total,
                                &si,
                                bsdf,
                                wo,
                                wo_local,
                                sampler,
                                rays,
                            );
                        if scene.lights.has_delta {
                            l += beta
                                * self.sample_light(
                                    scene, true, &si, bsdf, wo, wo_local, sampler, rays,
                                );
                        }
                    }
                }
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
            if pane && bs.wi.z * wo_local.z < 0.0 {
                // Straight through a pane: the same line, so MIS keeps the previous vertex.
                panes += 1;
                if panes > MAX_PANES {
                    break;
                }
                segments -= 1;
                ray = Ray::new(offset_origin(si.p, si.ng, wi), wi);
                continue;
            }
            if at_limit {
                break;
            }
            panes = 0;
            prev = Previous {
                p: si.p,
                n: si.ns,
                side,
                portal_total,
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
