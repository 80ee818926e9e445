//! Denoising features: each pixel's albedo and shading normal, the guides a denoiser (Intel
//! Open Image Denoise) reads beside the noisy image to keep edges and textures sharp.
//!
//! A feature sample follows the camera ray through mirrors and smooth glass (each delta
//! vertex picks one lobe as light would, so glass comes out as the Fresnel blend of what is
//! reflected and what is seen through it, as OIDN's documentation and Cycles' denoising
//! albedo do) to the first surface with a non-delta lobe, and reads there the surface's
//! directional albedo for the ray (one BSDF sample's weight f cos / pdf, whose mean is that
//! albedo: exactly the reflectance for a Lambertian surface) and its shading normal, turned
//! towards the ray (world space). A ray that escapes reads the environment's radiance,
//! clamped to [0, 1], and no normal.
//!
//! The features do not depend on the integrator: the drivers take one feature sample beside
//! each of a pixel's first [`FEATURE_SAMPLES`] kept samples, from a stream of its own, so
//! that pieces of a render split by sample ranges or tiles merge into the same sums. They
//! are held in fixed point with 24 fractional bits: integer sums, the same for any order.

use crate::light::LightHit;
use crate::render_scene::RenderScene;
use crate::sample_context::SampleContext;
use fenestra_core::stats::RayCounters;
use fenestra_core::{Frame, Ray, Rgb, Sampler, Vec3};

/// Feature samples a pixel takes at most: enough for anti-aliased guides, few enough to cost
/// a few percent of a render of as many samples or fewer, and nothing beyond.
pub const FEATURE_SAMPLES: u32 = 16;

/// The random stream feature samples draw from (no integrator uses it).
const FEATURE_STREAM: u32 = u32::MAX;

/// Delta vertices a feature sample follows before it gives up (a hall of mirrors).
const MAX_DELTA_VERTICES: u32 = 16;

/// Scale of the fixed-point sums: 2^24 units per unit.
const UNIT: f32 = 16_777_216.0;

/// One feature sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Feature {
    /// Albedo in [0, 1] per channel.
    pub albedo: Rgb,
    /// Unit shading normal facing the viewer, or zero where the ray escaped.
    pub normal: Vec3,
}

impl Feature {
    /// The feature read at the first non-delta vertex of a path whose throughput there is
    /// `throughput`: the surface's albedo estimated by its BSDF sample's weight `sampled`
    /// (none: no direction was sampled), plus the light `emitted` there, and its shading
    /// normal `ns` turned towards the ray's direction `d`.
    pub fn at_surface(
        throughput: Rgb,
        sampled: Option<Rgb>,
        emitted: Rgb,
        ns: Vec3,
        d: Vec3,
    ) -> Self {
        let albedo = clamped(sampled.map_or(Rgb::ZERO, clamped) + clamped(emitted));
        Feature {
            albedo: clamped(throughput * albedo),
            normal: if ns.dot(d) > 0.0 { -ns } else { ns },
        }
    }

    /// The feature of a path with throughput `throughput` that escapes along `d`: the
    /// environment's radiance there, clamped, and no normal.
    pub fn escaped(scene: &RenderScene, throughput: Rgb, d: Vec3) -> Self {
        let sky = (scene.lights.environments.iter())
            .map(|&e| scene.lights.lights[e].le(LightHit::Escaped, d))
            .fold(Rgb::ZERO, |a, b| a + b);
        Feature {
            albedo: clamped(throughput * clamped(sky)),
            normal: Vec3::ZERO,
        }
    }
}

/// One pixel's feature sums.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FeaturePixel {
    /// Sum of the albedo samples per channel, in units of 2^-24.
    pub albedo: [i32; 3],
    /// Sum of the normal samples per axis, in units of 2^-24.
    pub normal: [i32; 3],
    /// Feature samples added.
    pub count: u32,
}

fn fixed(v: f32, lo: f32) -> i32 {
    (v.clamp(lo, 1.0) * UNIT).round() as i32
}

impl FeaturePixel {
    /// Adds one feature sample.
    pub fn add(&mut self, f: &Feature) {
        let albedo = f.albedo.to_array();
        let normal = f.normal.to_array();
        for c in 0..3 {
            self.albedo[c] += fixed(albedo[c], 0.0);
            self.normal[c] += fixed(normal[c], -1.0);
        }
        self.count += 1;
    }

    /// Adds the sums of `other` (other samples of the same pixel); false, and the pixel
    /// unchanged, if a sum or the count would overflow.
    pub fn checked_merge(&mut self, other: &FeaturePixel) -> bool {
        let add = |a: [i32; 3], b: [i32; 3]| -> Option<[i32; 3]> {
            Some([
                a[0].checked_add(b[0])?,
                a[1].checked_add(b[1])?,
                a[2].checked_add(b[2])?,
            ])
        };
        let (Some(albedo), Some(normal), Some(count)) = (
            add(self.albedo, other.albedo),
            add(self.normal, other.normal),
            self.count.checked_add(other.count),
        ) else {
            return false;
        };
        *self = FeaturePixel {
            albedo,
            normal,
            count,
        };
        true
    }

    /// Whether the sums could come from `count` samples (each albedo in [0, 1], each normal
    /// component in [-1, 1]): the reason if not.
    pub fn impossible(&self) -> Option<String> {
        let most = i64::from(self.count) * UNIT as i64;
        let albedo = self
            .albedo
            .iter()
            .all(|&s| (0..=most).contains(&i64::from(s)));
        let normal = (self.normal.iter()).all(|&s| (-most..=most).contains(&i64::from(s)));
        (!(albedo && normal))
            .then(|| format!("has feature sums beyond what {} samples make", self.count))
    }

    /// The mean albedo.
    pub fn albedo(&self) -> Rgb {
        let n = self.count.max(1) as f32 * UNIT;
        Rgb::new(
            self.albedo[0] as f32 / n,
            self.albedo[1] as f32 / n,
            self.albedo[2] as f32 / n,
        )
    }

    /// The mean normal (not renormalised: edges and escaped samples shorten it).
    pub fn normal(&self) -> Vec3 {
        let n = self.count.max(1) as f32 * UNIT;
        Vec3::new(
            self.normal[0] as f32 / n,
            self.normal[1] as f32 / n,
            self.normal[2] as f32 / n,
        )
    }
}

/// `c` clamped to [0, 1] per channel (non-finite values to 0): what OIDN takes as albedo.
pub fn clamped(c: Rgb) -> Rgb {
    c.map(|v| {
        if v.is_finite() {
            v.clamp(0.0, 1.0)
        } else {
            0.0
        }
    })
}

/// Whether sample `index` of a pixel takes a feature sample beside it.
pub fn takes_feature(index: u32) -> bool {
    index < FEATURE_SAMPLES
}

/// Feature sample `ctx.index` of the pixel `ctx`, from its own stream of `seed`.
pub fn feature_sample(scene: &RenderScene, ctx: &SampleContext, seed: u64) -> Feature {
    let mut sampler = Sampler::in_stream(seed, FEATURE_STREAM, ctx.pixel(), ctx.index);
    // Feature rays are not the render's: they stay out of its ray counts.
    let mut ray = ctx.camera_ray(
        &scene.scene.camera,
        &mut sampler,
        &mut RayCounters::default(),
    );
    let mut weight = Rgb::ONE;
    for _ in 0..MAX_DELTA_VERTICES {
        let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
            return Feature::escaped(scene, weight, ray.d);
        };
        let si = scene.scene.interaction(&ray, &hit);
        let emitted = (scene.lights.surface_emission(&si, ray.d)).map_or(Rgb::ZERO, |(_, le)| le);
        let bsdf = scene.bsdf_at(&si);
        let frame = if bsdf.needs_tangent() {
            si.shading_frame()
        } else {
            Frame::from_normal(si.ns)
        };
        let (uc, u) = (sampler.next_1d(), sampler.next_2d());
        let sampled = bsdf.sample(frame.to_local(-ray.d), uc, u);
        match sampled {
            Some(bs) if bsdf.is_delta() => {
                weight *= bs.weight;
                let wi = frame.to_world(bs.wi);
                ray = Ray::new(si.spawn(wi), wi);
            }
            sampled => {
                let albedo = sampled.map(|bs| bs.weight);
                return Feature::at_surface(weight, albedo, emitted, si.ns, ray.d);
            }
        }
    }
    Feature {
        albedo: Rgb::ZERO,
        normal: Vec3::ZERO,
    }
}
