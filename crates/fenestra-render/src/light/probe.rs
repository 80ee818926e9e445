//! Direct light at a point as the path tracers estimate it, on a white diffuse surface: what
//! the pilots that choose a sampling strategy before rendering measure (whether portals pay,
//! whether the lights at infinity are worth a sample each at every vertex). Values are
//! luminance times cosine over density (irradiance estimates).

use super::{LightContext, LightHit, LightSampler, Picks};
use crate::integrator::{beyond_glass, Sides};
use crate::render_scene::RenderScene;
use fenestra_core::{warp, Frame, Ray, Sampler, Vec3};
use fenestra_scene::SurfaceInteraction;
use std::f32::consts::FRAC_1_PI;

/// Reflectance of the surfaces the pilots' paths bounce off: a middling interior's.
pub const ALBEDO: f64 = 0.5;

/// A point the camera sees, as a white diffuse surface facing it.
pub struct DiffuseProbe<'a> {
    /// The scene.
    pub scene: &'a RenderScene,
    /// The point.
    pub si: &'a SurfaceInteraction,
    /// What the light samplers see of it (the normal on the side facing the camera).
    pub ctx: LightContext<'a>,
}

impl<'a> DiffuseProbe<'a> {
    /// The point `si` of `scene`, on the side that faces `viewer`; `ctx`'s sample is `sample`.
    pub fn facing(
        scene: &'a RenderScene,
        si: &'a SurfaceInteraction,
        viewer: Vec3,
        sample: &'a crate::sample_context::SampleContext,
    ) -> Self {
        let n = if si.ng.dot(viewer - si.p) < 0.0 {
            -si.ng
        } else {
            si.ng
        };
        DiffuseProbe {
            scene,
            si,
            ctx: LightContext { p: si.p, n, sample },
        }
    }

    /// Density of the cosine-weighted direction `wi`.
    pub fn bsdf_pdf(&self, wi: Vec3) -> f64 {
        (wi.dot(self.ctx.n).max(0.0) * FRAC_1_PI) as f64
    }

    /// `lights`' density of `wi` towards light `index` met at `hit`.
    pub fn light_pdf(
        &self,
        lights: &dyn LightSampler,
        index: usize,
        wi: Vec3,
        hit: LightHit,
    ) -> f64 {
        let scene = self.scene;
        lights.pdf_li(&scene.scene, &scene.lights, &self.ctx, index, wi, hit) as f64
    }

    /// One next-event estimate by `lights` (every light it picks), taken with probability
    /// `share` (only compact lights count with `compact_only`), weighted against a cosine
    /// sample by the balance heuristic. Also returns the shadow rays it costs: one per light
    /// picked (per compact light picked with `compact_only`, a pick of the sky beside portals
    /// being dropped before any ray).
    pub fn light_estimate(
        &self,
        lights: &dyn LightSampler,
        compact_only: bool,
        share: f32,
        sampler: &mut Sampler,
    ) -> (f64, usize) {
        let (u_pick, u) = (sampler.next_1d(), sampler.next_2d());
        let mut picks = Picks::default();
        lights.sample_all(&self.ctx, u_pick, &mut picks);
        let scene = self.scene;
        let (mut sum, mut rays) = (0.0, 0);
        for &pick in picks.as_slice() {
            if compact_only && !scene.lights.lights[pick.0].is_compact() {
                continue;
            }
            rays += 1;
            let Some(ls) = lights.sample_li(&scene.scene, &scene.lights, &self.ctx, pick, u) else {
                continue;
            };
            let cos = ls.wi.dot(self.ctx.n);
            let p = share as f64 * ls.pdf as f64;
            if cos <= 0.0 || !(p > 0.0) {
                continue;
            }
            let (ray, tmax) = self.si.shadow_ray(ls.wi, ls.point);
            let tr = scene.transmittance(ray, tmax);
            let le = (tr * ls.li).luminance() as f64 * cos as f64;
            sum += if ls.delta {
                le / p
            } else {
                le / (p + self.bsdf_pdf(ls.wi))
            };
        }
        (sum, rays)
    }

    /// A cosine-weighted direction.
    pub fn cosine_direction(&self, sampler: &mut Sampler) -> Vec3 {
        let local = warp::square_to_cosine_hemisphere(sampler.next_2d());
        Frame::from_normal(self.ctx.n).to_world(local)
    }

    /// A cosine-weighted sample along `wi`, which found the lights `found`, weighted against
    /// `lights` by the balance heuristic.
    pub fn bsdf_estimate(&self, lights: &dyn LightSampler, wi: Vec3, found: &[Found]) -> f64 {
        let (pdf, cos) = (self.bsdf_pdf(wi), wi.dot(self.ctx.n) as f64);
        if !(pdf > 0.0) {
            return 0.0;
        }
        found
            .iter()
            .map(|f| {
                let light_pdf = if f.refracted {
                    0.0
                } else {
                    self.light_pdf(lights, f.light, wi, f.hit())
                };
                f.le * cos / (pdf + light_pdf)
            })
            .sum()
    }

    /// The lights a ray from the point along `wi` meets beyond thin glass.
    pub fn found(&self, wi: Vec3) -> Vec<Found> {
        self.look(wi, 0).0
    }

    /// The lights a ray from the point along `wi` meets beyond thin glass and through up to
    /// `refractions` smooth-glass interfaces (as lp_hf's portal samples and the paths that
    /// refract there find them).
    pub fn found_through(&self, wi: Vec3, refractions: u32) -> Vec<Found> {
        self.look(wi, refractions).0
    }

    /// The lights a ray from the point along `wi` meets beyond thin glass (and up to
    /// `refractions` smooth-glass interfaces), and the surface it meets (with the glass's
    /// transmittance's luminance) when it meets one.
    pub fn look(
        &self,
        wi: Vec3,
        refractions: u32,
    ) -> (Vec<Found>, Option<(SurfaceInteraction, f64)>) {
        let ray = Ray::new(self.si.spawn(wi), wi);
        let beyond = beyond_glass(self.scene, ray, refractions, Sides::Shading);
        let (tr, d, refracted) = (beyond.tr, beyond.d, beyond.refracted);
        let lights = &self.scene.lights;
        match beyond.surface {
            Some(s) => {
                let found = lights
                    .surface_emission(&s, d)
                    .map(|(light, le)| Found {
                        light,
                        le: (tr * le).luminance() as f64,
                        compact: false,
                        refracted,
                        surface: Some(s),
                    })
                    .into_iter()
                    .collect();
                (found, Some((s, tr.luminance() as f64)))
            }
            None => {
                let found = (lights.environments.iter())
                    .map(|&e| Found {
                        light: e,
                        le: (tr * lights.lights[e].le(LightHit::Escaped, d)).luminance() as f64,
                        compact: lights.lights[e].is_compact(),
                        refracted,
                        surface: None,
                    })
                    .collect();
                (found, None)
            }
        }
    }
}

/// A light a ray met (on a surface, or escaping) and the luminance it brings.
pub struct Found {
    /// The light.
    pub light: usize,
    /// Its luminance along the ray (through any glass on the way).
    pub le: f64,
    /// Whether it is a compact light ([`super::Light::is_compact`]).
    pub compact: bool,
    /// Whether the ray was refracted on the way (no light sampler's shadow ray finds it).
    pub refracted: bool,
    surface: Option<SurfaceInteraction>,
}

impl Found {
    /// Where the ray met it.
    pub fn hit(&self) -> LightHit<'_> {
        match &self.surface {
            Some(si) => LightHit::Surface(si),
            None => LightHit::Escaped,
        }
    }
}

/// Running sums for a sample variance.
#[derive(Default)]
pub struct Moments {
    n: f64,
    sum: f64,
    sum2: f64,
}

impl Moments {
    /// Adds a sample.
    pub fn add(&mut self, x: f64) {
        self.n += 1.0;
        self.sum += x;
        self.sum2 += x * x;
    }

    /// The variance of one sample (unbiased).
    pub fn variance(&self) -> f64 {
        if self.n < 2.0 {
            return 0.0;
        }
        let mean = self.sum / self.n;
        ((self.sum2 - self.n * mean * mean) / (self.n - 1.0)).max(0.0)
    }
}
