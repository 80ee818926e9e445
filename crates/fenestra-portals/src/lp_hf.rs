//! `lp_hf` (seed 000 ch. 4): next-event estimation through light portals. A portal is picked
//! and a direction through it sampled (eq. 4.1, or by solid angle); the ray finds whatever
//! lies beyond (an emitter, or the environment for sky-lit interiors, which the seed does not
//! treat) and is combined with BSDF sampling by MIS. Compact lights keep their own light
//! sampling: Dirac lights, which no ray finds, and the sun, which a portal's directions meet
//! too rarely to carry; optionally a share of the samples comes from light sampling
//! (a one-sample mixture, as Cycles mixes its portals with environment sampling).
//!
//! The portals come from the scene, a portals.json file, or an estimate made while the
//! integrator is prepared (so its time counts in the render's).

use crate::aim::camera_surroundings;
use crate::error::PortalError;
use crate::pilot::measure;
use crate::portal::{PickWeights, PortalChoice, PortalRecord, PortalSampling, Portals};
use crate::source::{Estimation, PortalSource, Sourced};
use fenestra_core::mis::MisHeuristic;
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_core::{Ray, Rgb, Sampler, Vec3};
use fenestra_render::integrator::{
    Beyond, Found, LightNextEvent, LightRays, NextEvent, PathOptions, PathTracer, ProbeRay,
    Scattered, Shading, MAX_REFRACTIONS,
};
use fenestra_render::light::{LightContext, LightHit, LightRecords, SplitSuns};
use fenestra_render::options::{OptionError, Options, Validate};
use fenestra_render::path_sample::PathSample;
use fenestra_render::sample_context::SampleContext;
use fenestra_render::{IntegratorError, RenderControl, RenderScene};
use serde_json::json;

fenestra_render::options! {
    /// Light portals: how lp_hf samples them.
    #[derive(Copy)]
    pub struct PortalOptions in "portal", flags "portal" {
        /// How a point is chosen on a portal: solid-angle (rectangles by the solid angle they
        /// subtend, Urena et al. 2013, where area sampling would spread the density of
        /// directions by more than 3x) or area (seed 000 eq. 4.1).
        pub sampling: PortalSampling = PortalSampling::SolidAngle,
        /// How a portal is picked: contribution (solid angle times cosine at the point),
        /// facing (uniform among those not behind the surface, as Cycles) or uniform (the
        /// seed's).
        pub choice: PortalChoice = PortalChoice::Contribution,
        /// Probability that a sample comes from light sampling instead of the portals (Cycles
        /// mixes its portals with environment sampling; 0 uses the portals only).
        pub light_mix: f32 = 0.0,
        /// Keep the portals even when, measured before rendering at the points the camera
        /// sees, light sampling alone (af_hf's) is the more efficient.
        pub keep: bool = false,
        /// With compact lights (Dirac lights, the sun): the probability that a vertex samples
        /// them instead of the portals, one ray per vertex (default: measured before rendering
        /// along with whether the portals pay; with portal.keep, both at every vertex).
        pub compact_share: Option<f32> = None,
    }
}

impl Validate for PortalOptions {
    fn validate(&self) -> Result<(), OptionError> {
        if self.compact_share.is_some_and(|c| !(c > 0.0 && c < 1.0)) {
            return Err(OptionError::new(
                "compact_share",
                format!(
                    "must lie in (0, 1), got {}",
                    self.compact_share.unwrap_or_default()
                ),
            ));
        }
        if !(0.0..=1.0).contains(&self.light_mix) {
            return Err(OptionError::new(
                "light_mix",
                format!("must lie in [0, 1], got {}", self.light_mix),
            ));
        }
        Ok(())
    }
}

/// The lp_hf integrator: the shared path loop with portal sampling (by `options`, from
/// `source`) as its next event, and `lights` (any light sampler: by power, uniform, a light
/// tree) for the share of light sampling and for Dirac lights.
pub fn lp_hf(
    path: PathOptions,
    options: PortalOptions,
    source: PortalSource,
    lights: LightNextEvent,
) -> Result<PathTracer<PortalNextEvent>, OptionError> {
    portal_path_tracer("lp_hf", path, options, source, lights)
}

/// lp_hf's path tracer as integrator `name` says it (in its errors and notes).
pub fn portal_path_tracer(
    name: &'static str,
    path: PathOptions,
    options: PortalOptions,
    source: PortalSource,
    lights: LightNextEvent,
) -> Result<PathTracer<PortalNextEvent>, OptionError> {
    options.check()?;
    let lights = if options.light_mix > 0.0 {
        lights.one_at_a_time().ok_or_else(|| {
            OptionError::new(
                "portal.light_mix",
                "draws one light at a time: not with a light sampler whose estimates take \
                 several (light.selection all or split, bvh.split, learned.suns split)",
            )
        })?
    } else {
        lights
    };
    Ok(PathTracer::new(
        "lp_hf",
        PortalNextEvent {
            name,
            options,
            source,
            portals: Portals::default(),
            found: Portals::default(),
            lights,
            estimated: None,
            none_found: false,
            gain: None,
            compact_share: options.compact_share,
        },
        path,
    ))
}

/// Portal sampling, mixed with light sampling, as a next-event strategy.
pub struct PortalNextEvent {
    /// The integrator's name, for its errors and notes.
    name: &'static str,
    options: PortalOptions,
    source: PortalSource,
    /// The portals, with the sampling and choice rules (set when prepared).
    portals: Portals,
    /// The portals the source gave, sampled or not (light paths enter through them).
    found: Portals,
    lights: LightNextEvent,
    /// How the portals were estimated, when they were.
    estimated: Option<Estimation>,
    /// The estimate (made now or cached) holds no portal: the lights are sampled alone.
    none_found: bool,
    /// The portals' efficiency over light sampling alone, measured before rendering (below 1:
    /// the portals were left out).
    gain: Option<f64>,
    /// The probability that a vertex samples the compact lights instead of the portals (the
    /// option's, or measured), or `None`: both at every vertex.
    compact_share: Option<f32>,
}

/// The portals as portals.json records.
fn records(portals: &Portals) -> serde_json::Value {
    json!(portals
        .portals()
        .iter()
        .map(PortalRecord::new)
        .collect::<Vec<_>>())
}

/// Where the portals come from, for an integrator's settings: once prepared (`portals` in
/// use), an estimate's settings also say which portals it found.
pub(crate) fn source_settings(source: &PortalSource, portals: &Portals) -> serde_json::Value {
    match source {
        PortalSource::Scene => json!("scene"),
        PortalSource::Given(p) => records(p),
        PortalSource::Estimated { params, .. } if !portals.is_empty() => {
            json!({ "estimated": params, "found": records(portals) })
        }
        PortalSource::Estimated { params, .. } => json!({ "estimated": params }),
    }
}

/// What lp_hf keeps of a shading vertex: the portals' pick weights there, for the side light
/// may arrive from (computed once per vertex, used by the sample and by the MIS weight of the
/// next BSDF-sampled ray).
#[derive(Clone, Copy, Debug, Default)]
pub struct PortalVertex {
    weights: PickWeights,
}

impl PortalNextEvent {
    /// The portals in use (empty before preparation).
    pub fn portals(&self) -> &Portals {
        &self.portals
    }

    /// The portals the source gave, also where sampling them did not pay (empty before
    /// preparation).
    pub fn found_portals(&self) -> &Portals {
        &self.found
    }

    /// The probabilities that a vertex samples the compact lights and the portals: both 1
    /// when it samples both, else one or the other.
    fn shares(&self, scene: &RenderScene) -> (f32, f32) {
        match self.compact_share {
            Some(c) if scene.lights.has_compact => (c, 1.0 - c),
            _ => (1.0, 1.0),
        }
    }

    /// Portal sampling at `s` (eq. 4.1), or with probability `light_mix` light sampling: a
    /// direction, and the probe ray that finds whatever lies beyond thin glass along it
    /// (emitter or environment), and for portal samples beyond the refractions of smooth
    /// glass too (a glazed window); [`PortalNextEvent::probed`] weighs that by MIS against
    /// the BSDF with the mixture's density.
    fn sample_portal(
        &self,
        scene: &RenderScene,
        s: &Shading,
        v: &PortalVertex,
        mis: MisHeuristic,
        sampler: &mut Sampler,
        rays: &mut RayCounters,
    ) -> Option<ProbeRay<PortalProbe>> {
        let light_mix = self.options.light_mix;
        let by_light = light_mix > 0.0 && sampler.next_1d() < light_mix;
        let u_pick = sampler.next_1d();
        let u = sampler.next_2d();
        let si = s.si;
        // The light sampled in light mode: only it may be found along the ray (as a shadow
        // ray would have it), so the mixture density counts that light's density alone.
        let (wi, sampled, portal_pdf) = if by_light {
            let ctx = s.light_context();
            let sampler = self.lights.sampler();
            let pick = sampler.sample(&ctx, u_pick)?;
            // Compact lights have their own estimator.
            if scene.lights.lights[pick.0].is_compact() {
                return None;
            }
            let ls = sampler.sample_li(&scene.scene, &scene.lights, &ctx, pick, u)?;
            let index = pick.0;
            (ls.wi, Some(index), None)
        } else {
            let ps = self.portals.sample(&v.weights, u_pick, u)?;
            (ps.wi, None, Some(ps.pdf))
        };
        let (wi_local, f) = s.bsdf_toward(wi)?;
        rays.shadow += 1;
        Some(ProbeRay {
            ray: Ray::new(si.spawn(wi), wi),
            beta: Rgb::ONE,
            // A light sample's direction points at a point of the light: refracted, it would
            // miss it (the light sampler's density is that of the straight line).
            refractions: if by_light { 0 } else { MAX_REFRACTIONS },
            probe: PortalProbe {
                p: si.p,
                n: si.ns,
                cos: wi_local.z.abs(),
                f,
                bsdf_pdf: s.bsdf.pdf(s.wo_local, wi_local),
                sampled,
                portal_pdf: portal_pdf.unwrap_or_else(|| self.portals.pdf(&v.weights, wi)),
                share: 1.0,
                mis,
            },
        })
    }
}

/// What lp_hf keeps of a portal (or light) sample while its probe ray is traced.
#[derive(Clone, Copy, Debug)]
pub struct PortalProbe {
    /// The shading point and its shading normal (what the light sampler saw).
    p: Vec3,
    n: Vec3,
    /// |cos| of the direction at the point, and the BSDF there.
    cos: f32,
    f: Rgb,
    /// The BSDF's density of the direction, for MIS.
    bsdf_pdf: f32,
    /// The light sampled in light mode: the only one the ray may find.
    sampled: Option<usize>,
    /// The portals' density of the direction.
    portal_pdf: f32,
    /// The probability that the vertex sampled the portals (one of them and the compact
    /// lights per vertex), else 1.
    share: f32,
    mis: MisHeuristic,
}

impl NextEvent for PortalNextEvent {
    type Vertex = PortalVertex;
    type Probe = PortalProbe;

    fn settings(&self) -> serde_json::Value {
        let portals = source_settings(&self.source, &self.portals);
        let mut s = json!({ "portals": portals, "portal": self.options });
        if let (Some(all), serde_json::Value::Object(lights)) =
            (s.as_object_mut(), self.lights.settings())
        {
            all.extend(lights);
        }
        s
    }

    fn prepare(
        &mut self,
        scene: &RenderScene,
        control: &RenderControl,
    ) -> Result<(), IntegratorError> {
        self.lights.prepare(scene, control)?;
        let Sourced {
            portals,
            estimation,
            surroundings,
        } = self.source.portals(scene, control)?;
        self.estimated = estimation;
        if estimation.is_some() && portals.is_empty() {
            control.progress.note(&format!(
                "portals: none found that carries light to what the camera sees; \
                 {} samples the lights alone, as af_hf does",
                self.name
            ));
            self.none_found = true;
            return Ok(());
        }
        if portals.is_empty() {
            return Err(PortalError::NoPortals(self.name).into());
        }
        self.found = portals.clone();
        let portals = portals.with_strategy(self.options.sampling, self.options.choice);
        // Beside the portals, which carry the sky, the suns take a light sample at every
        // vertex: the other lights' picks, when the sampler splits, cost no ray there.
        let mut verdict = None;
        let (keep, share) = (self.options.keep, self.options.compact_share);
        self.lights.replace_sampler(|lights| {
            let suns = SplitSuns::new(lights, &scene.lights);
            if keep {
                return Box::new(suns);
            }
            // Where the estimate aimed, or found out now.
            let surroundings = surroundings.unwrap_or_else(|| camera_surroundings(&scene.scene));
            let measured = measure(scene, &portals, (suns.inner(), &suns), &surroundings, share);
            let pays = measured.gain() >= 1.0;
            verdict = Some(measured);
            if pays {
                Box::new(suns)
            } else {
                suns.into_inner()
            }
        });
        if let Some(verdict) = verdict {
            self.gain = Some(verdict.gain());
            self.compact_share = verdict.compact_share;
            let rays = format!(
                "{:.2} rays per vertex with the portals, {:.2} without",
                verdict.portal_rays, verdict.light_rays
            );
            if verdict.gain() < 1.0 {
                control.progress.note(&format!(
                    "portals: light sampling alone measured {:.2}x as efficient at the points \
                     the camera sees ({rays}); {} samples the lights alone, as af_hf does \
                     (--portal-keep keeps the portals)",
                    1.0 / verdict.gain(),
                    self.name
                ));
                return Ok(());
            }
            let how = match verdict.compact_share {
                Some(c) if scene.lights.has_compact => format!(
                    "; a vertex samples the compact lights with probability {c:.2}, else the \
                     portals"
                ),
                _ => String::new(),
            };
            control.progress.note(&format!(
                "portals: measured {:.2}x as efficient as light sampling alone at the points \
                 the camera sees ({rays}){how}",
                verdict.gain()
            ));
        }
        self.portals = portals;
        Ok(())
    }

    fn learning(&self) -> bool {
        self.lights.learning()
    }

    fn learns(&self, pass: u32) -> bool {
        self.lights.learns(pass)
    }

    fn learn(&self, blocks: &[LightRecords]) {
        self.lights.learn(blocks);
    }

    fn vertex(&self, _: &RenderScene, s: &Shading) -> PortalVertex {
        // Light reaches an opaque surface from the side `wo` leaves on; a transmissive one
        // from both.
        let side = (!s.bsdf.is_transmissive()).then(|| s.si.ng * s.si.ng.dot(s.wo).signum());
        PortalVertex {
            weights: self.portals.pick_weights(s.si.p, side),
        }
    }

    fn sample(
        &self,
        scene: &RenderScene,
        s: &Shading,
        v: &PortalVertex,
        mis: MisHeuristic,
        sample: &mut PathSample,
        out: &mut LightRays<PortalProbe>,
    ) -> Rgb {
        if self.portals.is_empty() {
            // No portal was found: af_hf's light sampling.
            let shadows = &mut out.shadows;
            self.lights
                .sample_light(scene, s, false, mis, sample, shadows);
            return Rgb::ZERO;
        }
        let (compact, through) = self.shares(scene);
        // One strategy or both at this vertex.
        let u = match self.compact_share {
            Some(_) if scene.lights.has_compact => sample.sampler.next_1d(),
            _ => f32::NAN,
        };
        if !(u < compact) {
            if let Some(mut probe) =
                self.sample_portal(scene, s, v, mis, sample.sampler, sample.rays)
            {
                probe.probe.share = through;
                out.probes.push(probe);
            }
        }
        if scene.lights.has_compact && !(u >= compact) {
            let shadows = &mut out.shadows;
            self.lights
                .sample_light_share(scene, s, (true, compact), mis, sample, shadows);
        }
        Rgb::ZERO
    }

    /// The radiance found beyond the probe's glass (an emitter the sample may find, or the
    /// environment), weighted by MIS against the BSDF with the mixture's density.
    fn probed(
        &self,
        scene: &RenderScene,
        probe: &PortalProbe,
        _ray: &Ray,
        beyond: &Beyond,
        sample: &SampleContext,
    ) -> Rgb {
        let light_mix = self.options.light_mix;
        // Light arrives along the probe's last segment (refracted by glazing, or its own).
        let wi = beyond.d;
        // Only the portals' samples follow refractions: light found so has no light-sampling
        // density.
        let light_mix_found = if beyond.refracted { 0.0 } else { light_mix };
        let ctx = LightContext {
            p: probe.p,
            n: probe.n,
            sample,
        };
        let light_sampler = self.lights.sampler();
        let seen = |index: usize| probe.sampled.is_none_or(|s| s == index);
        let tr = beyond.tr;
        // Radiance found beyond and the light sampler's density of that direction.
        let (li, light_pdf) = match &beyond.surface {
            Some(surface) => match scene.lights.surface_emission(surface, wi) {
                Some((index, le)) if seen(index) => {
                    let pdf = if light_mix_found > 0.0 {
                        let hit = LightHit::Surface(surface);
                        light_sampler.pdf_li(&scene.scene, &scene.lights, &ctx, index, wi, hit)
                    } else {
                        0.0
                    };
                    (tr * le, pdf)
                }
                _ => (Rgb::ZERO, 0.0),
            },
            // The sun is its own estimator's: portals leave it.
            None => (scene.lights.environments.iter())
                .filter(|&&e| seen(e) && !scene.lights.lights[e].is_compact())
                .fold((Rgb::ZERO, 0.0), |(l, pdf), &e| {
                    let light = &scene.lights.lights[e];
                    (
                        l + tr * light.le(LightHit::Escaped, wi),
                        pdf + light_sampler.pdf_li(
                            &scene.scene,
                            &scene.lights,
                            &ctx,
                            e,
                            wi,
                            LightHit::Escaped,
                        ),
                    )
                }),
        };
        if li.is_black() {
            return Rgb::ZERO;
        }
        let pdf =
            probe.share * ((1.0 - light_mix) * probe.portal_pdf + light_mix_found * light_pdf);
        if !(pdf > 0.0) {
            return Rgb::ZERO;
        }
        let weight = probe.mis.weight(pdf, probe.bsdf_pdf);
        probe.f * li * (probe.cos * weight / pdf)
    }

    /// Whether portal samples follow refractions: whenever there are portals (without, lp_hf
    /// is af_hf).
    fn follows_refraction(&self) -> bool {
        !self.portals.is_empty()
    }

    /// The portal density of `wi`, whatever the ray found beyond, mixed with the light
    /// sampler's density by `light_mix` (zero for light found through refractions, which
    /// the compact lights' shadow rays and light samples do not follow).
    fn pdf(
        &self,
        scene: &RenderScene,
        from: &Scattered<PortalVertex>,
        wi: Vec3,
        found: Found,
        sample: &SampleContext,
    ) -> f32 {
        let ctx = from.light_context(sample);
        // A compact light (the sun) found by the BSDF's ray competes with its own light
        // sampling alone, and so does any light when there is no portal.
        if self.portals.is_empty() {
            return self.lights.light_pdf(scene, &ctx, wi, found);
        }
        let (compact, through) = self.shares(scene);
        if scene.lights.lights[found.light].is_compact() {
            return compact * self.lights.light_pdf(scene, &ctx, wi, found);
        }
        let v = &from.vertex;
        let light_mix = self.options.light_mix;
        let mut p = (1.0 - light_mix) * self.portals.pdf(&v.weights, wi);
        if light_mix > 0.0 {
            p += light_mix * self.lights.light_pdf(scene, &ctx, wi, found);
        }
        through * p
    }

    /// As [`PortalNextEvent::sample`] takes lights: all of them where there are no portals,
    /// else the compact ones, with the probability that the vertex samples them.
    fn light_pick(&self, scene: &RenderScene, ctx: &LightContext, light: usize) -> f32 {
        if self.portals.is_empty() {
            return self.lights.light_pick(ctx, light);
        }
        if !scene.lights.lights[light].is_compact() {
            return 0.0;
        }
        self.shares(scene).0 * self.lights.light_pick(ctx, light)
    }

    fn report(&self, stats: &mut RenderStats) {
        self.lights.report(stats);
        stats
            .extra
            .insert("portals".into(), self.portals.portals().len() as f64);
        match self.estimated {
            Some(Estimation::Made { photons, seconds }) => {
                stats.extra.insert("portal_photons".into(), photons as f64);
                stats.extra.insert("portal_estimation_s".into(), seconds);
            }
            Some(Estimation::Cached) => {
                stats.extra.insert("portals_cached".into(), 1.0);
            }
            None => {}
        }
        if self.none_found {
            stats.extra.insert("portals_none_found".into(), 1.0);
        }
        if let Some(gain) = self.gain {
            stats.extra.insert("portal_gain".into(), gain);
        }
        if let Some(c) = self.compact_share {
            stats.extra.insert("portal_compact_share".into(), c as f64);
        }
    }
}
