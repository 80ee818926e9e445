//! Whether portals pay (beyond seed 000): lp_hf must never be worse than af_hf. Before
//! rendering, at the points the camera sees, both next-event estimators (cosine-weighted, as
//! on a diffuse surface) are sampled side by side: af_hf's (a light picked by the light
//! sampler, a point on it) and lp_hf's (a direction through the portals finding the sky or an
//! emitter beyond, plus the light sampler's compact lights), of the direct light there and of
//! the direct light of the surface a cosine sample finds, reflected at [`ALBEDO`] (as the
//! default light selection's pilot measures: on a sunlit room the noise is mostly the sun's
//! bounce, which portals do not sample). Their variances summed over the points, times the
//! rays each spends per path vertex (counted: the BSDF's, a shadow ray per light picked, a
//! portal's probe ray), say which is more efficient. lp_hf's compact lights are measured with
//! the sampler it renders them with beside portals (each sun at every vertex); with the sun a
//! coin toss beside them, Bitterli's classroom measured its portals at 0.88x, with the sun at
//! every vertex 1.50x (rendered: 1.30x af_hf's efficiency).

use crate::aim::Surroundings;
use crate::portal::PickWeights;
use crate::portal::Portals;
use fenestra_core::Sampler;
use fenestra_render::integrator::MAX_REFRACTIONS;
use fenestra_render::light::probe::{DiffuseProbe, Moments, ALBEDO};
use fenestra_render::light::LightSampler;
use fenestra_render::sample_context::SampleContext;
use fenestra_render::RenderScene;

/// Samples of each estimator at each point.
const SAMPLES: u32 = 8;
/// Points of the surroundings used at most.
const POINTS: usize = 2048;

/// The estimators' measured variance times cost, and how lp_hf should sample.
#[derive(Clone, Copy, Debug)]
pub struct Verdict {
    /// Portals (with compact lights by light sampling), as lp_hf samples with
    /// `compact_share`.
    pub portals: f64,
    /// Light sampling alone, as af_hf samples.
    pub lights: f64,
    /// The probability that a vertex samples the compact lights instead of the portals, or
    /// `None` for both at every vertex, whichever measured the more efficient.
    pub compact_share: Option<f32>,
    /// Rays per path vertex of the portals' estimator (taken with `compact_share`).
    pub portal_rays: f64,
    /// Rays per path vertex of light sampling alone.
    pub light_rays: f64,
}

impl Verdict {
    /// How many times as efficient the portals are as light sampling alone (infinite when
    /// light sampling has no variance left to lose and the portals none either).
    pub fn gain(&self) -> f64 {
        if self.portals > 0.0 {
            self.lights / self.portals
        } else if self.lights > 0.0 {
            f64::INFINITY
        } else {
            1.0
        }
    }
}

/// How lp_hf's portal estimator is taken in a measurement: both strategies at a vertex, or
/// the compact lights with probability `compact` and else the portals.
#[derive(Clone, Copy)]
enum Plan {
    Both,
    OneOf { compact: f32 },
}

/// Measures the estimators at the camera's `surroundings` in `scene`: light sampling alone
/// (by `lights`), and the portals with the compact lights (sampled by `compact`) at every
/// vertex or (chosen per vertex with `compact_share`, else the probability that minimises the
/// variance measured) one or the other.
pub fn measure(
    scene: &RenderScene,
    portals: &Portals,
    (lights, compact): (&dyn LightSampler, &dyn LightSampler),
    surroundings: &Surroundings,
    compact_share: Option<f32>,
) -> Verdict {
    let samplers = Samplers { lights, compact };
    if !scene.lights.has_compact {
        let m = moments(scene, portals, samplers, surroundings, Plan::Both);
        return m.verdict(None);
    }
    if let Some(c) = compact_share {
        let m = moments(
            scene,
            portals,
            samplers,
            surroundings,
            Plan::OneOf { compact: c },
        );
        return m.verdict(Some(c));
    }
    let both = moments(scene, portals, samplers, surroundings, Plan::Both);
    // A sum of two estimators taken one at a time with probabilities c and 1 - c has the
    // variance M_c / c + M_p / (1 - c) - mean^2, least at c = sqrt(M_c) / (sqrt(M_c) +
    // sqrt(M_p)).
    let (mc, mp) = (both.second_compact.sqrt(), both.second_portals.sqrt());
    let c = if mc + mp > 0.0 {
        (mc / (mc + mp)) as f32
    } else {
        0.5
    };
    let c = c.clamp(MIN_SHARE, 1.0 - MIN_SHARE);
    let one_of = moments(
        scene,
        portals,
        samplers,
        surroundings,
        Plan::OneOf { compact: c },
    );
    if one_of.portals * one_of.rays.portals < both.portals * both.rays.portals {
        one_of.verdict(Some(c))
    } else {
        both.verdict(None)
    }
}

/// The least probability of either strategy when one is taken per vertex.
const MIN_SHARE: f32 = 0.05;

/// Variances (summed over the points) of the two estimators, and the second moments of the
/// portal estimator's two parts.
struct Measured {
    portals: f64,
    lights: f64,
    /// Rays per vertex of each estimator.
    rays: Rays,
    second_compact: f64,
    second_portals: f64,
}

impl Measured {
    fn verdict(&self, compact_share: Option<f32>) -> Verdict {
        Verdict {
            portals: self.portals * self.rays.portals,
            lights: self.lights * self.rays.lights,
            compact_share,
            portal_rays: self.rays.portals,
            light_rays: self.rays.lights,
        }
    }
}

/// The light samplers of the two estimators: light sampling alone, and the compact lights'
/// beside the portals.
#[derive(Clone, Copy)]
struct Samplers<'a> {
    lights: &'a dyn LightSampler,
    compact: &'a dyn LightSampler,
}

fn moments(
    scene: &RenderScene,
    portals: &Portals,
    samplers: Samplers,
    surroundings: &Surroundings,
    plan: Plan,
) -> Measured {
    let camera = scene.scene.camera.position;
    let points = &surroundings.points;
    let step = points.len().div_ceil(POINTS).max(1);
    let context = SampleContext::SINGLE;
    let mut m = Measured {
        portals: 0.0,
        lights: 0.0,
        rays: Rays::default(),
        second_compact: 0.0,
        second_portals: 0.0,
    };
    let (mut rays, mut estimates) = (Rays::default(), 0.0);
    for (k, si) in points.iter().enumerate().step_by(step) {
        let at = Point::new(
            DiffuseProbe::facing(scene, si, camera, &context),
            samplers,
            portals,
        );
        let mut sampler = Sampler::new(0, 0x5049_4c54, k as u32);
        let (mut lp, mut af) = (Moments::default(), Moments::default());
        for _ in 0..SAMPLES {
            let mut e = at.estimates(plan, &mut sampler);
            let wi = at.probe.cosine_direction(&mut sampler);
            if let (_, Some((y, tr))) = at.probe.look(wi, 0) {
                let probe = DiffuseProbe::facing(scene, &y, si.p, &context);
                let bounce = Point::new(probe, samplers, portals).estimates(plan, &mut sampler);
                e.add_reflected(&bounce, ALBEDO * tr);
            }
            rays.add(e.rays);
            estimates += e.vertices;
            m.second_compact += e.compact * e.compact;
            m.second_portals += e.portals * e.portals;
            lp.add(e.with_portals);
            af.add(e.with_lights);
        }
        m.portals += lp.variance();
        m.lights += af.variance();
    }
    m.rays = if estimates > 0.0 {
        Rays {
            portals: rays.portals / estimates,
            lights: rays.lights / estimates,
        }
    } else {
        Rays {
            portals: 2.0,
            lights: 2.0,
        }
    };
    m
}

/// Rays spent by each estimator: the BSDF's, a shadow ray per light picked (per compact light
/// beside the portals), a portal sample's probe ray.
#[derive(Clone, Copy, Default)]
struct Rays {
    portals: f64,
    lights: f64,
}

impl Rays {
    fn add(&mut self, other: Rays) {
        self.portals += other.portals;
        self.lights += other.lights;
    }
}

/// A point the camera sees, as a white diffuse surface facing it, and the samplers at it.
/// Each estimator combines its samples with a cosine-weighted (BSDF) sample by the balance
/// heuristic, as the path tracers do.
struct Point<'a> {
    probe: DiffuseProbe<'a>,
    samplers: Samplers<'a>,
    portals: &'a Portals,
    weights: PickWeights,
}

/// Both estimators' values at a point, or summed over a path's points.
struct Estimates {
    /// lp_hf's: its compact lights' and portals' samples and the BSDF sample.
    with_portals: f64,
    /// af_hf's: its light sample and the BSDF sample.
    with_lights: f64,
    /// The compact lights' part of `with_portals`.
    compact: f64,
    /// The portals' part of `with_portals`.
    portals: f64,
    /// Rays each estimator spent, and at how many vertices.
    rays: Rays,
    vertices: f64,
}

impl Estimates {
    /// Adds the estimates at the next vertex, whose light reaches this one times `k`.
    fn add_reflected(&mut self, next: &Estimates, k: f64) {
        self.with_portals += k * next.with_portals;
        self.with_lights += k * next.with_lights;
        self.compact += k * next.compact;
        self.portals += k * next.portals;
        self.rays.add(next.rays);
        self.vertices += next.vertices;
    }
}

impl<'a> Point<'a> {
    fn new(probe: DiffuseProbe<'a>, samplers: Samplers<'a>, portals: &'a Portals) -> Self {
        Point {
            weights: portals.pick_weights(probe.si.p, Some(probe.ctx.n)),
            probe,
            samplers,
            portals,
        }
    }

    /// One sample of each estimator at the point, lp_hf's taken by `plan`.
    fn estimates(&self, plan: Plan, sampler: &mut Sampler) -> Estimates {
        let (compact, through) = match plan {
            Plan::Both => (1.0, 1.0),
            Plan::OneOf { compact } => (compact, 1.0 - compact),
        };
        let (by_bsdf_portals, by_bsdf_lights) = self.bsdf_sample((compact, through), sampler);
        let (all, picked) = self.light_sample(false, 1.0, sampler);
        // (value, shadow rays) of the compact lights' sample and of the portals'.
        let ((c, shadow), p) = match plan {
            Plan::Both => (
                self.light_sample(true, 1.0, sampler),
                (self.portal_sample(1.0, sampler), 1),
            ),
            Plan::OneOf { compact } if sampler.next_1d() < compact => {
                (self.light_sample(true, compact, sampler), (0.0, 0))
            }
            Plan::OneOf { .. } => ((0.0, 0), (self.portal_sample(through, sampler), 1)),
        };
        let (p, probe) = p;
        Estimates {
            with_portals: c + p + by_bsdf_portals,
            with_lights: all + by_bsdf_lights,
            compact: c,
            portals: p,
            rays: Rays {
                portals: (1 + shadow + probe) as f64,
                lights: (1 + picked) as f64,
            },
            vertices: 1.0,
        }
    }

    /// A next-event estimate by the light sampler (with `compact_only`, by the compact
    /// lights' sampler, only compact lights counting), taken with probability `share`, and the
    /// shadow rays it cost.
    fn light_sample(&self, compact_only: bool, share: f32, sampler: &mut Sampler) -> (f64, usize) {
        let lights = if compact_only {
            self.samplers.compact
        } else {
            self.samplers.lights
        };
        (self.probe).light_estimate(lights, compact_only, share, sampler)
    }

    /// A direction through the portals, finding what lies beyond thin glass and through
    /// refracting glazing (the sun left to light sampling), taken with probability `share`.
    fn portal_sample(&self, share: f32, sampler: &mut Sampler) -> f64 {
        let (u_pick, u) = (sampler.next_1d(), sampler.next_2d());
        let Some(ps) = self.portals.sample(&self.weights, u_pick, u) else {
            return 0.0;
        };
        let cos = ps.wi.dot(self.probe.ctx.n);
        if cos <= 0.0 || !(ps.pdf > 0.0) {
            return 0.0;
        }
        let found = self.probe.found_through(ps.wi, MAX_REFRACTIONS);
        let le: f64 = found.iter().filter(|f| !f.compact).map(|f| f.le).sum();
        le * cos as f64 / (share as f64 * ps.pdf as f64 + self.probe.bsdf_pdf(ps.wi))
    }

    /// A cosine-weighted direction: its balance-weighted value against the portals' mixture
    /// (portals for what they carry, light sampling for compact lights, taken with the
    /// probabilities `shares`) and against light sampling alone.
    fn bsdf_sample(&self, (compact, through): (f32, f32), sampler: &mut Sampler) -> (f64, f64) {
        let probe = &self.probe;
        let wi = probe.cosine_direction(sampler);
        let (pdf, cos) = (probe.bsdf_pdf(wi), wi.dot(probe.ctx.n) as f64);
        if !(pdf > 0.0) {
            return (0.0, 0.0);
        }
        let portal_pdf = through as f64 * self.portals.pdf(&self.weights, wi) as f64;
        // Through glazing as the paths refract (light sampling finds none of that light).
        let found = probe.found_through(wi, MAX_REFRACTIONS);
        let mut with_portals = 0.0;
        for f in &found {
            let strategy = if f.refracted && f.compact {
                0.0
            } else if f.compact {
                compact as f64 * probe.light_pdf(self.samplers.compact, f.light, wi, f.hit())
            } else {
                portal_pdf
            };
            with_portals += f.le * cos / (pdf + strategy);
        }
        (
            with_portals,
            probe.bsdf_estimate(self.samplers.lights, wi, &found),
        )
    }
}
