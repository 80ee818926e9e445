//! Iterative adaptive sampling of direct light (seed 004 ch. 3-4): integrator `ias`.
//!
//! The image is rendered in 8x8 pixel blocks, each independently to completion (§3.3.2): its
//! pixels' points are found once, as sub-pixel regions of similar eye-ray hits (the adaptive
//! anti-aliasing of §3.6), with a cut through the light-cluster forest at each (§3.5.1);
//! environments join the cuts as 300 regions of directions (module `sky`), distant lights as
//! one cluster each. Then passes: at each point a PDF over the clusters of its cut blends
//! uniform, block and pixel statistics (eq. 3.2) in proportion to C / sqrt(u) (eq. 3.7, App.
//! A.2), kept per normal class (§3.5.4); lights inside a cluster are picked by power; 1.5 N_C
//! shadow rays per pixel per pass (at least 50, at most 150 after pass 0; §4.6.1). Each
//! pass's pixel estimate and its conservative variance (App. A.1) are combined over passes
//! (by inverse variance, eq. 3.3-3.4, or by rays) until the relative variance falls below the
//! threshold, with a top-up in steps of 25 rays near it (§4.6.1), the undersampling guard
//! (§4.6.2), at most 15 passes and the black-pixel rule (3 passes and 250 shadow rays
//! without a visible light; §4.6.4).
//!
//! Not yet: the visualisations. Direct light only, as the seed: a camera ray that meets a
//! mirror or glass gets nothing beyond what it sees emitted.

use crate::forest::{Forest, CUT_SOLID_ANGLE, NO_PARENT};
use crate::sky::{self, SkyRegion, SKY_REGIONS};
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_core::{Ray, Rgb, Sampler, Vec2, Vec3};
use fenestra_render::bsdf::Bsdf;
use fenestra_render::control::RenderControl;
use fenestra_render::integrator::{Integrator, IntegratorError};
use fenestra_render::light::{LightHit, LightSample};
use fenestra_render::{Film, RenderScene, RenderSettings};
use fenestra_scene::SurfaceInteraction;
use rayon::prelude::*;

/// Side of a block.
const BLOCK: u32 = 8;
/// Most eye rays a pixel takes (three surfaces' worth at 25 each); its shadow rays' sample
/// streams come after them.
const MAX_EYE_RAYS: u32 = 75;

/// Eye rays per unique surface in a pixel by image size (§4.6.3): 25 up to 512x512, 20 up
/// to 1024x1024, 15 beyond.
fn rays_per_surface(width: u32, height: u32) -> u32 {
    match u64::from(width) * u64::from(height) {
        0..=262_144 => 25,
        262_145..=1_048_576 => 20,
        _ => 15,
    }
}

/// A sub-pixel region (§3.6): its first hit and how many eye rays it gathered.
struct Region {
    shape: usize,
    material: usize,
    /// How far from its first hit a ray's hit may join it.
    radius: f32,
    rays: u32,
    point: Point,
}

/// How a pixel's pass estimates are combined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Combine {
    /// By inverse variance (eq. 3.3, 3.4): the seed's, least variance, but the variances
    /// come from the same samples as the estimates, so a pass that missed a bright light
    /// (low estimate, low variance) weighs more: the image comes out darker (measured in
    /// docs/manylights.md).
    InverseVariance,
    /// By shadow rays: every ray weighs the same, whatever pass it came in; unbiased.
    Samples,
}

/// Where the PDFs over a point's lights come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pdf {
    /// The seed's adaptive PDFs over light clusters (eq. 3.2).
    Adaptive,
    /// The seed's reference (§4.2): over single lights, in proportion to their unoccluded
    /// irradiance at the point (their bounds' importance), the same throughout; 100 rays a
    /// pass, at most 20,000 a pixel, black after 2,500 rays without a visible light.
    Irradiance,
}

/// The seed's parameters.
#[derive(Clone, Copy, Debug)]
pub struct IasOptions {
    /// Relative variance of a pixel at which it is done (t of §3.5.3).
    pub threshold: f32,
    /// Most passes per block.
    pub max_passes: u32,
    /// Cluster size bound of the cuts, in steradians.
    pub solid_angle: f32,
    /// How the passes' estimates of a pixel are combined.
    pub combine: Combine,
    /// Adaptive (ias) or the seed's reference.
    pub pdf: Pdf,
    /// Regions an environment is cut into for the adaptive sampler (the seed's 300; 0
    /// takes each environment whole, as one cluster).
    pub sky_regions: usize,
}

impl Default for IasOptions {
    fn default() -> Self {
        IasOptions {
            threshold: 1e-3,
            max_passes: 15,
            solid_angle: CUT_SOLID_ANGLE,
            combine: Combine::Samples,
            pdf: Pdf::Adaptive,
            sky_regions: SKY_REGIONS,
        }
    }
}

impl IasOptions {
    /// The seed's reference estimator with termination threshold `threshold`: every light
    /// its own cluster, PDFs by unoccluded irradiance, every ray weighing the same.
    pub fn reference(threshold: f32) -> Self {
        IasOptions {
            threshold,
            max_passes: REFERENCE_MAX_RAYS / REFERENCE_PASS_RAYS,
            solid_angle: f32::MIN_POSITIVE,
            combine: Combine::Samples,
            pdf: Pdf::Irradiance,
            sky_regions: 0,
        }
    }

    /// Shadow rays without a visible light after which a pixel is black (§4.6.4).
    fn black_after(&self) -> u32 {
        match self.pdf {
            Pdf::Adaptive => 250,
            Pdf::Irradiance => 2500,
        }
    }
}

/// The reference's rays per pass and its cap per pixel (§4.2, §4.6.4).
const REFERENCE_PASS_RAYS: u32 = 100;
const REFERENCE_MAX_RAYS: u32 = 20_000;

/// The `ias` integrator.
pub struct Ias {
    options: IasOptions,
    forest: Option<Forest>,
    /// The clusters outside the forest, numbered after its nodes.
    far: Vec<Far>,
}

/// A cluster outside the forest: a light at infinity taken whole, or a region of an
/// environment's directions.
#[derive(Clone, Copy, Debug)]
enum Far {
    Light(usize),
    Region(SkyRegion),
}

impl Ias {
    /// `ias` with `options`.
    pub fn new(options: IasOptions) -> Result<Self, IntegratorError> {
        let o = options;
        if !(o.threshold > 0.0 && o.threshold.is_finite()) {
            return Err(IntegratorError::Options(format!(
                "the ias threshold must be positive, got {}",
                o.threshold
            )));
        }
        if o.max_passes == 0 || !(o.solid_angle > 0.0 && o.solid_angle.is_finite()) {
            return Err(IntegratorError::Options(
                "ias needs at least one pass and a positive cluster solid angle".into(),
            ));
        }
        Ok(Ias {
            options,
            forest: None,
            far: Vec::new(),
        })
    }
}

/// Weights (uniform, block, pixel) of the PDFs combined in pass `j` (eq. 3.2): uniform only
/// at first, then mostly the block, then mostly the pixel (the shape of the seed's Fig. 3.5,
/// whose values the text does not give); the uniform part never vanishes.
fn weights(pass: u32) -> [f32; 3] {
    match pass {
        0 => [1.0, 0.0, 0.0],
        1 => [0.3, 0.5, 0.2],
        2 => [0.2, 0.45, 0.35],
        3 => [0.15, 0.35, 0.5],
        4 => [0.1, 0.25, 0.65],
        _ => [0.1, 0.15, 0.75],
    }
}

/// A feedback PDF over a cut from its clusters' statistics (eq. 3.8): in proportion to
/// F = C / sqrt(u). With `guard` (the block PDF, §4.6.2), a cluster without samples, or with
/// fewer than four all occluded, gets the mean F of the others instead of its own. `None`
/// when nothing has weight yet.
fn component(stats: &[Stat], guard: bool) -> Option<Vec<f64>> {
    let raw: Vec<Option<f64>> = stats
        .iter()
        .map(|s| {
            if guard && (s.count == 0 || s.count < 4 && s.visible == 0) {
                None
            } else {
                Some(s.weight().unwrap_or(0.0))
            }
        })
        .collect();
    let known: Vec<f64> = raw.iter().flatten().copied().collect();
    let mean = if known.is_empty() {
        0.0
    } else {
        known.iter().sum::<f64>() / known.len() as f64
    };
    let f: Vec<f64> = raw.iter().map(|r| r.unwrap_or(mean)).collect();
    let total: f64 = f.iter().sum();
    (total > 0.0 && total.is_finite()).then(|| f.iter().map(|v| v / total).collect())
}

/// The PDF of pass `pass` over `n` clusters (eq. 3.2): the uniform, block and pixel PDFs by
/// the pass's weights, a missing feedback PDF's weight given to the uniform one. Every
/// cluster keeps at least the uniform part's probability.
fn blend(n: usize, pass: u32, block: Option<Vec<f64>>, pixel: Option<Vec<f64>>) -> Vec<f32> {
    let [mut cu, cb, cp] = weights(pass).map(f64::from);
    if block.is_none() {
        cu += cb;
    }
    if pixel.is_none() {
        cu += cp;
    }
    (0..n)
        .map(|i| {
            let b = block.as_ref().map_or(0.0, |b| cb * b[i]);
            let p = pixel.as_ref().map_or(0.0, |p| cp * p[i]);
            (cu / n as f64 + b + p) as f32
        })
        .collect()
}

/// Which of six classes a normal falls in (the cube face it points to, §3.5.4).
fn normal_class(n: Vec3) -> usize {
    let a = n.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    2 * axis + usize::from(n[axis] < 0.0)
}

/// Running sums of the evaluations of one cluster (eq. 3.6 and the visible fraction u).
#[derive(Clone, Copy, Debug, Default)]
struct Stat {
    sum: f64,
    count: u32,
    visible: u32,
}

impl Stat {
    /// F = C / sqrt(u) (eq. 3.7), `None` without samples.
    fn weight(&self) -> Option<f64> {
        if self.count == 0 {
            return None;
        }
        let c = self.sum / self.count as f64;
        let u = self.visible as f64 / self.count as f64;
        Some(if u > 0.0 { c / u.sqrt() } else { 0.0 })
    }
}

/// A point to shade: where an eye ray met a surface.
struct Point {
    si: SurfaceInteraction,
    bsdf: Bsdf,
    /// Towards the eye.
    wo: Vec3,
    /// Normal on the eye's side.
    n: Vec3,
    class: usize,
    /// Share of the pixel.
    area: f32,
    /// The clusters of its cut (forest nodes; past the forest's nodes, lights at infinity).
    cut: Vec<u32>,
}

/// One pixel of the block.
struct PixelState {
    x: u32,
    y: u32,
    points: Vec<Point>,
    /// What the eye rays see emitted (no shadow ray), and the variance of that mean over
    /// the eye rays, per channel.
    emitted: Rgb,
    emitted_variance: [f64; 3],
    /// Over the passes, with pass weights w: sum w, sum w I (per channel), and the sums
    /// w^2 s^2 of the luminance's and each channel's variance.
    weight: f64,
    weighted: [f64; 3],
    variance: f64,
    channel_variance: [f64; 3],
    passes: u32,
    shadow_rays: u32,
    rays_before: u32,
    seen_light: bool,
    done: bool,
    /// Next index of the pixel's sample stream.
    next_sample: u32,
    /// Its rows of the pixel statistics: node slot -> stat, per class present.
    stats: Vec<(usize, Vec<Stat>)>,
}

impl PixelState {
    /// The combined estimate (eq. 3.4 with the pass weights), the variance of its luminance
    /// (eq. 3.3 for inverse-variance weights) and of each channel.
    fn estimate(&self) -> ([f64; 3], f64, [f64; 3]) {
        if self.weight <= 0.0 {
            return ([0.0; 3], 0.0, [0.0; 3]);
        }
        let w2 = self.weight * self.weight;
        (
            self.weighted.map(|v| v / self.weight),
            self.variance / w2,
            self.channel_variance.map(|v| v / w2),
        )
    }

    /// The estimate and luminance variance if a pass (`estimate`, `s2`) of weight `w` joined.
    fn with_pass(&self, estimate: [f64; 3], s2: f64, w: f64) -> (f64, f64) {
        let weight = self.weight + w;
        let mean = (luminance(self.weighted) + w * luminance(estimate)) / weight;
        (mean, (self.variance + w * w * s2) / (weight * weight))
    }
}

/// What a block's render gives back.
struct BlockResult {
    pixels: Vec<(u32, u32, [f64; 3], [f64; 3])>,
    rays: RayCounters,
    passes: u64,
    shadow_rays: u64,
    cut_sizes: u64,
    points: u64,
    max_passes: u32,
}

impl Integrator for Ias {
    fn name(&self) -> &str {
        match self.options.pdf {
            Pdf::Adaptive => "ias",
            Pdf::Irradiance => "ias_reference",
        }
    }

    fn settings(&self) -> serde_json::Value {
        serde_json::json!({
            "threshold": self.options.threshold,
            "max_passes": self.options.max_passes,
            "solid_angle": self.options.solid_angle,
            "sky_regions": self.options.sky_regions,
            "pdf": match self.options.pdf {
                Pdf::Adaptive => "adaptive",
                Pdf::Irradiance => "irradiance",
            },
            "combine": match self.options.combine {
                Combine::InverseVariance => "inverse-variance",
                Combine::Samples => "samples",
            },
        })
    }

    fn prepare(&mut self, scene: &RenderScene, _: &RenderControl) -> Result<(), IntegratorError> {
        let forest = Forest::new(&scene.scene, &scene.lights);
        // The adaptive sampler sees environments as the seed's 300 regions; the reference
        // takes them whole.
        let lights = &scene.lights;
        self.far = match self.options.pdf {
            Pdf::Adaptive if self.options.sky_regions > 0 => {
                let others = forest.infinite.iter().copied();
                let others = others.filter(|l| !lights.environments.contains(l));
                sky::regions(lights, self.options.sky_regions)
                    .into_iter()
                    .map(Far::Region)
                    .chain(others.map(Far::Light))
                    .collect()
            }
            _ => forest.infinite.iter().map(|&l| Far::Light(l)).collect(),
        };
        self.forest = Some(forest);
        Ok(())
    }

    fn render(
        &self,
        scene: &RenderScene,
        film: &mut Film,
        settings: &RenderSettings,
        control: &RenderControl,
    ) -> RenderStats {
        let empty = Forest {
            nodes: Vec::new(),
            roots: Vec::new(),
            infinite: Vec::new(),
        };
        let forest = self.forest.as_ref().unwrap_or(&empty);
        let (width, height) = (film.width, film.height);
        let (bx, by) = (width.div_ceil(BLOCK), height.div_ceil(BLOCK));
        control.progress.start(Some(u64::from(bx * by)));
        let results: Vec<Option<BlockResult>> = (0..bx * by)
            .into_par_iter()
            .map(|b| {
                if control.cancelled() {
                    return None;
                }
                let r = BlockRender {
                    ias: self,
                    forest,
                    scene,
                    seed: settings.seed,
                    width,
                    height,
                }
                .render((b % bx) * BLOCK, (b / bx) * BLOCK);
                control.progress.advance(1);
                Some(r)
            })
            .collect();
        let mut stats = RenderStats {
            scene: scene.scene.name.clone(),
            backend: scene.scene.backend.name().to_string(),
            width,
            height,
            seed: settings.seed,
            threads: rayon::current_num_threads(),
            max_depth: Some(2),
            ..Default::default()
        };
        let (mut passes, mut shadow, mut cuts, mut points) = (0u64, 0u64, 0u64, 0u64);
        for r in &results {
            let Some(r) = r else {
                stats.interrupted = true;
                continue;
            };
            for &(x, y, mean, var) in &r.pixels {
                film.pixels[(y * width + x) as usize].set_estimate(mean, var);
            }
            stats.rays += r.rays;
            passes += r.passes;
            shadow += r.shadow_rays;
            cuts += r.cut_sizes;
            points += r.points;
        }
        let pixels = f64::from(width * height).max(1.0);
        stats.passes = results
            .iter()
            .flatten()
            .map(|r| r.max_passes)
            .max()
            .unwrap_or(0);
        // Eye rays per pixel stand for samples per pixel.
        let eye = stats.rays.camera as f64 / pixels;
        stats.spp = eye.round() as u32;
        stats.spp_max = stats.spp;
        stats.extra.insert("eye_rays_per_pixel".into(), eye);
        stats
            .extra
            .insert("passes_per_pixel".into(), passes as f64 / pixels);
        stats
            .extra
            .insert("shadow_rays_per_pixel".into(), shadow as f64 / pixels);
        stats.extra.insert(
            "clusters_per_cut".into(),
            cuts as f64 / points.max(1) as f64,
        );
        stats.time_s = control.elapsed();
        stats.derive_rates();
        stats
    }
}

/// Everything a block's render reads.
struct BlockRender<'a> {
    ias: &'a Ias,
    forest: &'a Forest,
    scene: &'a RenderScene,
    seed: u64,
    width: u32,
    height: u32,
}

impl BlockRender<'_> {
    /// Renders the block at (x0, y0) to completion.
    fn render(&self, x0: u32, y0: u32) -> BlockResult {
        let mut rays = RayCounters::default();
        let mut pixels = Vec::new();
        for y in y0..(y0 + BLOCK).min(self.height) {
            for x in x0..(x0 + BLOCK).min(self.width) {
                pixels.push(self.pixel_points(x, y, &mut rays));
            }
        }
        // Slots of every cut node of the block (node ids past the forest's nodes are lights
        // at infinity).
        let node_count = self.forest.nodes.len() + self.ias.far.len();
        let mut slot = vec![u32::MAX; node_count];
        let mut nodes: Vec<u32> = Vec::new();
        for p in &pixels {
            for point in &p.points {
                for &c in &point.cut {
                    if slot[c as usize] == u32::MAX {
                        slot[c as usize] = nodes.len() as u32;
                        nodes.push(c);
                    }
                }
            }
        }
        let k = nodes.len();
        // Block statistics per normal class; pixel statistics per class present.
        let mut block: Vec<Vec<Stat>> = vec![vec![Stat::default(); k]; 6];
        for p in &mut pixels {
            let mut classes: Vec<usize> = p.points.iter().map(|q| q.class).collect();
            classes.sort_unstable();
            classes.dedup();
            p.stats = classes
                .into_iter()
                .map(|c| (c, vec![Stat::default(); k]))
                .collect();
        }
        let (mut cut_sizes, mut points) = (0u64, 0u64);
        for p in &pixels {
            for q in &p.points {
                cut_sizes += q.cut.len() as u64;
                points += 1;
            }
        }
        let mut cdf = Vec::new();
        for pass in 0..self.ias.options.max_passes {
            if pixels.iter().all(|p| p.done) {
                break;
            }
            let mut pass_block: Vec<Vec<Stat>> = vec![vec![Stat::default(); k]; 6];
            for p in pixels.iter_mut().filter(|p| !p.done) {
                self.pixel_pass(p, pass, &block, &slot, &mut pass_block, &mut cdf, &mut rays);
            }
            // Feedback (Step FB): this pass's block statistics join the earlier ones.
            for (all, new) in block.iter_mut().zip(&pass_block) {
                for (a, n) in all.iter_mut().zip(new) {
                    a.sum += n.sum;
                    a.count += n.count;
                    a.visible += n.visible;
                }
            }
        }
        let mut out = Vec::with_capacity(pixels.len());
        let (mut passes, mut shadow) = (0u64, 0u64);
        for p in &pixels {
            let (mean, _, shading) = p.estimate();
            let variance: [f64; 3] = std::array::from_fn(|c| shading[c] + p.emitted_variance[c]);
            let e = p.emitted;
            let mean = [
                mean[0] + e.r as f64,
                mean[1] + e.g as f64,
                mean[2] + e.b as f64,
            ];
            out.push((p.x, p.y, mean, variance));
            passes += u64::from(p.passes);
            shadow += u64::from(p.shadow_rays);
        }
        BlockResult {
            max_passes: pixels.iter().map(|p| p.passes).max().unwrap_or(0),
            pixels: out,
            rays,
            passes,
            shadow_rays: shadow,
            cut_sizes,
            points,
        }
    }

    /// Step 1 with the adaptive anti-aliasing of §3.6 and §4.6.3: eye rays through the
    /// pixel (25, 20 or 15 per unique surface by resolution, at most three surfaces' worth),
    /// grouped into sub-pixel regions: a hit joins a region of the same shape, material and
    /// plane within half the pixel's footprint radius of its first hit, else starts one.
    /// Each region's first hit is its point, its share of the rays its area, with a cut
    /// through the forest. What the rays see emitted is averaged over all of them.
    fn pixel_points(&self, x: u32, y: u32, rays: &mut RayCounters) -> PixelState {
        let scene = self.scene;
        let camera = &scene.scene.camera;
        let pixel = u64::from(y) * u64::from(self.width) + u64::from(x);
        let per_surface = rays_per_surface(self.width, self.height);
        // The pixel's angular size, for its footprint at a hit.
        let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        let d0 = camera.generate_ray(centre, self.width, self.height).d;
        let d1 = camera
            .generate_ray(centre + Vec2::X, self.width, self.height)
            .d;
        let pixel_angle = d0.angle_between(d1);
        let mut regions: Vec<Region> = Vec::new();
        // Sums of what each eye ray sees emitted, and of its squares.
        let (mut emitted, mut emitted_sq) = (Rgb::ZERO, [0.0f64; 3]);
        let mut see = |le: Rgb| {
            emitted += le;
            for (c, v) in le.to_array().into_iter().enumerate() {
                emitted_sq[c] += f64::from(v) * f64::from(v);
            }
        };
        let (mut traced, mut target, mut surfaces) = (0u32, per_surface, 0u32);
        while traced < target {
            let mut sampler = Sampler::new(self.seed, pixel, traced);
            traced += 1;
            let film = Vec2::new(x as f32, y as f32) + sampler.next_2d();
            let ray = camera.generate_ray(film, self.width, self.height);
            rays.camera += 1;
            let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
                let sky = scene.lights.environments.iter();
                see(sky.fold(Rgb::ZERO, |acc, &e| {
                    acc + scene.lights.lights[e].le(LightHit::Escaped, ray.d)
                }));
                continue;
            };
            let si = scene.scene.interaction(&ray, &hit);
            see(scene
                .lights
                .surface_emission(&si, ray.d)
                .map_or(Rgb::ZERO, |(_, le)| le));
            let material = scene.scene.shapes[si.shape].material;
            let n = if si.ng.dot(ray.d) <= 0.0 {
                si.ng
            } else {
                -si.ng
            };
            let same_surface = |r: &Region| {
                r.shape == si.shape
                    && r.material == material
                    && r.point.n.dot(n) > 0.999
                    && (si.p - r.point.si.p).dot(r.point.n).abs() <= 1e-4 * (1.0 + hit.t)
            };
            if !regions.iter().any(same_surface) {
                surfaces += 1;
                target = per_surface * surfaces.min(3);
            }
            if let Some(r) = regions
                .iter_mut()
                .find(|r| same_surface(r) && (si.p - r.point.si.p).length() <= r.radius)
            {
                r.rays += 1;
                continue;
            }
            let bsdf = scene.bsdf_at(&si).into_owned();
            let receiver = if bsdf.is_transmissive() {
                Vec3::ZERO
            } else {
                n
            };
            let mut cut = Vec::new();
            if !bsdf.is_delta() {
                self.forest
                    .cut(si.p, receiver, self.ias.options.solid_angle, &mut cut);
                let first_far = self.forest.nodes.len() as u32;
                for (k, far) in self.ias.far.iter().enumerate() {
                    if let Far::Region(r) = far {
                        if !r.above(receiver) {
                            continue;
                        }
                    }
                    cut.push(first_far + k as u32);
                }
            }
            regions.push(Region {
                shape: si.shape,
                material,
                radius: 0.5 * hit.t * pixel_angle,
                rays: 1,
                point: Point {
                    si,
                    bsdf,
                    wo: -ray.d,
                    n,
                    class: normal_class(n),
                    area: 0.0,
                    cut,
                },
            });
        }
        let share = 1.0 / traced as f32;
        let n = f64::from(traced);
        let mean = emitted * share;
        let emitted_variance = std::array::from_fn(|c| {
            let m = f64::from(mean.to_array()[c]);
            ((emitted_sq[c] / n - m * m) / (n - 1.0).max(1.0)).max(0.0)
        });
        let points: Vec<Point> = regions
            .into_iter()
            // Mirrors and glass get no direct light (the seed's scope): only what is seen
            // emitted there counts.
            .filter(|r| !r.point.cut.is_empty())
            .map(|r| Point {
                area: r.rays as f32 * share,
                ..r.point
            })
            .collect();
        PixelState {
            x,
            y,
            done: points.is_empty(),
            points,
            emitted: mean,
            emitted_variance,
            weight: 0.0,
            weighted: [0.0; 3],
            variance: 0.0,
            channel_variance: [0.0; 3],
            passes: 0,
            shadow_rays: 0,
            rays_before: 0,
            seen_light: false,
            next_sample: MAX_EYE_RAYS,
            stats: Vec::new(),
        }
    }

    /// One pass of one pixel (Steps 2-3): PDFs, samples, statistics, the pass estimate and
    /// its combination with the earlier passes, termination.
    #[allow(clippy::too_many_arguments)]
    fn pixel_pass(
        &self,
        p: &mut PixelState,
        pass: u32,
        block: &[Vec<Stat>],
        slot: &[u32],
        pass_block: &mut [Vec<Stat>],
        cdf: &mut Vec<f32>,
        rays: &mut RayCounters,
    ) {
        let options = &self.ias.options;
        // 1.5 N_C shadow rays for the pixel (N_C: the points' mean cut size), at least 50, at
        // most 150 after pass 0 (§4.6.1), shared among the points by area.
        let nc: f32 = p
            .points
            .iter()
            .map(|q| q.area * q.cut.len() as f32)
            .sum::<f32>()
            / p.points.iter().map(|q| q.area).sum::<f32>().max(1e-6);
        let mut budget = ((1.5 * nc).ceil() as u32).max(50);
        if pass > 0 {
            budget = budget.min(150);
        }
        let adaptive = options.pdf == Pdf::Adaptive;
        if !adaptive {
            budget = REFERENCE_PASS_RAYS;
        }
        // Each point's samples this pass.
        let mut sums: Vec<PointSums> = vec![PointSums::default(); p.points.len()];
        let pdfs: Vec<Vec<f32>> = (0..p.points.len())
            .map(|i| self.point_pdf(&p.points[i], p, pass, block, slot))
            .collect();
        let pixel_index = u64::from(p.y) * u64::from(self.width) + u64::from(p.x);
        let mut drawn = 0u32;
        let mut round = budget;
        loop {
            for (i, q) in p.points.iter().enumerate() {
                // No light can reach the point (the reference's PDF may say so exactly).
                if pdfs[i].iter().sum::<f32>() <= 0.0 {
                    continue;
                }
                let n = ((round as f32 * q.area).round() as u32).max(1);
                cdf.clear();
                let mut acc = 0.0;
                for &w in &pdfs[i] {
                    acc += w;
                    cdf.push(acc);
                }
                for _ in 0..n {
                    let mut sampler = Sampler::new(self.seed, pixel_index, p.next_sample);
                    p.next_sample = p.next_sample.wrapping_add(1);
                    let s = self.sample(q, &pdfs[i], cdf, &mut sampler, rays);
                    p.shadow_rays += 1;
                    p.seen_light |= s.visible;
                    sums[i].add(s.value);
                    let pixel = p.stats.iter_mut().find(|(c, _)| *c == q.class);
                    let stat = (s.leaf, s.contribution, s.power, s.visible);
                    let pixel = pixel.map(|(_, st)| st.as_mut_slice());
                    self.record(pixel, q.class, stat, slot, pass_block);
                }
                drawn += n;
            }
            let (estimate, s2, channels) = pass_estimate(&p.points, &sums);
            // Top-up (§4.6.1): when the pixel is within a factor of two of the threshold
            // with this pass, 25 more rays with the same PDFs.
            let w = self.pass_weight(p, s2);
            let (mean, var) = p.with_pass(estimate, s2, w);
            let relative = var / (mean * mean).max(f64::MIN_POSITIVE);
            let t = f64::from(options.threshold);
            if adaptive && relative >= t && relative < 2.0 * t && drawn < 4 * budget {
                round = 25;
                continue;
            }
            self.finish_pass(p, pass, estimate, s2, channels);
            break;
        }
    }

    /// The weight of a pass of luminance variance `s2` with the pixel's rays since its last
    /// pass: 1/s2 (eq. 3.3), or the rays.
    fn pass_weight(&self, p: &PixelState, s2: f64) -> f64 {
        let rays = f64::from((p.shadow_rays - p.rays_before).max(1));
        match self.ias.options.combine {
            Combine::Samples => rays,
            // A pass whose samples were all alike has no variance of its own: after passes
            // that had one it counts as informative per ray as they were (eq. 3.3 would give
            // it infinite weight); before any, it is all there is.
            Combine::InverseVariance if s2 > 0.0 => 1.0 / s2,
            Combine::InverseVariance if p.weight > 0.0 => {
                p.weight * rays / f64::from(p.rays_before.max(1))
            }
            Combine::InverseVariance => 1.0,
        }
    }

    /// Adds a pass's estimate to the pixel (eq. 3.3, 3.4) and decides whether it is done.
    fn finish_pass(
        &self,
        p: &mut PixelState,
        pass: u32,
        estimate: [f64; 3],
        s2: f64,
        channels: [f64; 3],
    ) {
        let options = &self.ias.options;
        p.passes = pass + 1;
        let w = self.pass_weight(p, s2);
        p.rays_before = p.shadow_rays;
        p.weight += w;
        p.variance += w * w * s2;
        for c in 0..3 {
            p.weighted[c] += w * estimate[c];
            p.channel_variance[c] += w * w * channels[c];
        }
        let (mean, var, _) = p.estimate();
        let m = luminance(mean);
        // Termination on relative variance (§3.5.3); samples all alike and lit are exact.
        let converged = m > 0.0 && var / (m * m) < f64::from(options.threshold);
        // The black-pixel rule (§4.6.4).
        let black = !p.seen_light && p.passes >= 3 && p.shadow_rays >= options.black_after();
        p.done = converged || black || p.passes >= options.max_passes;
    }

    /// The PDF over a point's cut for a pass (eq. 3.2, 3.7, 3.8), with the undersampling
    /// guard on the block part (§4.6.2).
    fn point_pdf(
        &self,
        q: &Point,
        p: &PixelState,
        pass: u32,
        block: &[Vec<Stat>],
        slot: &[u32],
    ) -> Vec<f32> {
        if self.ias.options.pdf == Pdf::Irradiance {
            return self.irradiance_pdf(q);
        }
        let of = |stats: &[Stat]| -> Vec<Stat> {
            q.cut
                .iter()
                .map(|&c| stats[slot[c as usize] as usize])
                .collect()
        };
        let pixel = p.stats.iter().find(|(c, _)| *c == q.class);
        blend(
            q.cut.len(),
            pass,
            component(&of(&block[q.class]), true),
            pixel.and_then(|(_, s)| component(&of(s), false)),
        )
    }

    /// The reference's PDF over a point's lights (§4.2): in proportion to each light's
    /// unoccluded irradiance bound at the point; lights at infinity, whose irradiance the
    /// bounds do not give, share the probability of one more light with the rest.
    fn irradiance_pdf(&self, q: &Point) -> Vec<f32> {
        let forest = self.forest;
        let n = if q.bsdf.is_transmissive() {
            Vec3::ZERO
        } else {
            q.n
        };
        let mut w: Vec<f64> = q
            .cut
            .iter()
            .map(|&c| match forest.nodes.get(c as usize) {
                Some(node) => f64::from(node.bounds.importance(q.si.p, n)),
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

    /// One light sample at point `q`.
    fn sample(
        &self,
        q: &Point,
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
            (
                node,
                self.ias.far[node as usize - forest.nodes.len()],
                1.0,
                1.0,
            )
        };
        let mut eval = LightEval {
            value: Rgb::ZERO,
            visible: false,
            leaf,
            contribution: 0.0,
            power,
        };
        let scene = self.scene;
        let s = match target {
            Far::Light(l) => {
                scene.lights.lights[l].sample_li(&scene.scene, q.si.p, sampler.next_2d())
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
        let frame = q.si.shading_frame();
        let (wo, wi) = (frame.to_local(q.wo), frame.to_local(s.wi));
        // Shading normals must not leak light through the surface.
        if !q.bsdf.is_transmissive() && (s.wi.dot(q.n) > 0.0) != (wi.z * wo.z > 0.0) {
            return eval;
        }
        let unoccluded = q.bsdf.eval(wo, wi) * wi.z.abs() * s.li / s.pdf;
        if unoccluded.is_black() || !unoccluded.is_finite() {
            return eval;
        }
        let origin = q.si.spawn(s.wi);
        let tmax = match s.point {
            Some(y) => (y - origin).length() * (1.0 - 1e-4),
            None => f32::INFINITY,
        };
        rays.shadow += 1;
        let seen = unoccluded * scene.transmittance(Ray::new(origin, s.wi), tmax);
        eval.visible = !seen.is_black();
        eval.contribution = f64::from(seen.luminance());
        eval.value = seen / (p_cluster * p_light);
        eval
    }

    /// Adds a sample of the light at `leaf` to the statistics of every cut node of the
    /// block above it (and of the pixel): at node a it estimates a's contribution as
    /// v P_a / P_leaf (lights inside a cluster are picked by power; §3.5.4).
    fn record(
        &self,
        mut pixel: Option<&mut [Stat]>,
        class: usize,
        (leaf, value, power, visible): (u32, f64, f32, bool),
        slot: &[u32],
        pass_block: &mut [Vec<Stat>],
    ) {
        let forest = self.forest;
        let mut node = leaf;
        loop {
            let s = slot[node as usize];
            if s != u32::MAX {
                let scale = if (node as usize) < forest.nodes.len() && power > 0.0 {
                    f64::from(forest.nodes[node as usize].power / power)
                } else {
                    1.0
                };
                for stat in std::iter::once(&mut pass_block[class][s as usize])
                    .chain(pixel.as_deref_mut().map(|px| &mut px[s as usize]))
                {
                    stat.sum += value * scale;
                    stat.count += 1;
                    stat.visible += u32::from(visible);
                }
            }
            if (node as usize) >= forest.nodes.len() {
                break;
            }
            let parent = forest.nodes[node as usize].parent;
            if parent == NO_PARENT {
                break;
            }
            node = parent;
        }
    }
}

/// A point's samples in a pass: sums of the values and of their squares per channel.
#[derive(Clone, Copy, Debug, Default)]
struct PointSums {
    sum: [f64; 3],
    sq: [f64; 3],
    n: u32,
}

impl PointSums {
    fn add(&mut self, v: Rgb) {
        for (c, x) in v.to_array().into_iter().enumerate() {
            self.sum[c] += f64::from(x);
            self.sq[c] += f64::from(x) * f64::from(x);
        }
        self.n += 1;
    }
}

/// What one light sample gives.
struct LightEval {
    /// Its contribution over its probability (the point's estimator).
    value: Rgb,
    /// Whether the shadow ray reached the light.
    visible: bool,
    /// The light's node (for the statistics).
    leaf: u32,
    /// The light's own contribution estimate (luminance, occlusion included).
    contribution: f64,
    /// The light's power.
    power: f32,
}

fn luminance(c: [f64; 3]) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// The seed's conservative estimate of the variance of a mean `m` of `n` samples whose
/// squares sum to `sum_sq` (App. A.1, eq. A.3): with V = sum x^2 / N^2 and
/// E = m / N - 3 sqrt(V) / N^2, s^2 = V if E < 0, else V - N E^2.
fn conservative_variance(m: f64, sum_sq: f64, n: f64) -> f64 {
    let v = sum_sq / (n * n);
    let e = m / n - 3.0 * v.sqrt() / (n * n);
    if e < 0.0 {
        v
    } else {
        (v - n * e * e).max(0.0)
    }
}

/// The pixel's estimate for a pass, I = sum over points of area x mean, and the
/// conservative variance of its mean (App. A.1, eq. A.3) in luminance and per channel. As
/// pixel values, the N samples of the pass are x_i = value x area x N / n_point, so that
/// their mean is I.
fn pass_estimate(points: &[Point], sums: &[PointSums]) -> ([f64; 3], f64, [f64; 3]) {
    let n: u32 = sums.iter().map(|s| s.n).sum();
    if n == 0 {
        return ([0.0; 3], 0.0, [0.0; 3]);
    }
    let big_n = f64::from(n);
    let (mut estimate, mut second) = ([0.0f64; 3], [0.0f64; 3]);
    for (q, s) in points.iter().zip(sums).filter(|(_, s)| s.n > 0) {
        let scale = f64::from(q.area) * big_n / f64::from(s.n);
        for c in 0..3 {
            estimate[c] += s.sum[c] * scale / big_n;
            second[c] += s.sq[c] * scale * scale;
        }
    }
    let conservative = |m: f64, sq: f64| conservative_variance(m, sq, big_n);
    let channels: [f64; 3] = std::array::from_fn(|c| conservative(estimate[c], second[c]));
    // The luminance's second moment needs the cross terms; its samples' squares are bounded
    // by the channels' (luminance is a convex combination), so this stays conservative.
    let lum_second = 0.2126 * second[0] + 0.7152 * second[1] + 0.0722 * second[2];
    (
        estimate,
        conservative(luminance(estimate), lum_second),
        channels,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The variance of one sample of two lights of exitant radiance L_i, visible fractions
    /// u_i, the first picked with probability p (App. A.2, eq. A.4).
    fn variance(p: f64, l: [f64; 2], u: [f64; 2]) -> f64 {
        let second = u[0] * l[0] * l[0] / p + u[1] * l[1] * l[1] / (1.0 - p);
        let mean = u[0] * l[0] + u[1] * l[1];
        second - mean * mean
    }

    #[test]
    fn c_over_sqrt_u_minimises_the_variance_of_partly_visible_lights() {
        for (l, u) in [
            ([1.0, 1.0], [1.0, 0.25]),
            ([3.0, 1.0], [0.1, 0.9]),
            ([0.5, 2.0], [0.6, 0.05]),
        ] {
            // The statistics such lights leave: C = u L as the mean contribution, u the
            // visible share (1000 samples each).
            let stat = |i: usize| Stat {
                sum: 1000.0 * u[i] * l[i],
                count: 1000,
                visible: (1000.0 * u[i]) as u32,
            };
            let pdf = component(&[stat(0), stat(1)], false).expect("weights");
            // The numerical minimum over p, on a fine grid.
            let best = (1..10_000)
                .map(|k| k as f64 / 10_000.0)
                .min_by(|&a, &b| variance(a, l, u).total_cmp(&variance(b, l, u)))
                .expect("grid");
            assert!(
                (pdf[0] - best).abs() < 2e-3,
                "L {l:?} u {u:?}: C/sqrt(u) gives {} where the variance is least at {best}",
                pdf[0]
            );
            // Proportional to contribution alone would be worse wherever u differ.
            let by_c = u[0] * l[0] / (u[0] * l[0] + u[1] * l[1]);
            assert!(variance(pdf[0], l, u) <= variance(by_c, l, u) + 1e-12);
        }
    }

    #[test]
    fn no_cluster_ever_gets_zero_probability() {
        // A cluster the feedback says is dark (sampled, never visible) still keeps the
        // uniform share of every pass: the estimator stays unbiased if the feedback is wrong.
        let dark = Stat {
            sum: 0.0,
            count: 40,
            visible: 0,
        };
        let lit = Stat {
            sum: 40.0,
            count: 40,
            visible: 40,
        };
        let stats = [lit, dark, lit];
        for pass in 0..20 {
            let pdf = blend(3, pass, component(&stats, true), component(&stats, false));
            let total: f32 = pdf.iter().sum();
            assert!((total - 1.0).abs() < 1e-5, "pass {pass}: sums to {total}");
            assert!(pdf[1] >= 0.1 / 3.0 - 1e-6, "pass {pass}: {pdf:?}");
        }
        // The guard: a cluster with under four samples, all occluded, is not trusted yet.
        let barely = Stat {
            sum: 0.0,
            count: 3,
            visible: 0,
        };
        let pdf = component(&[lit, barely], true).expect("weights");
        assert!(
            (pdf[0] - 0.5).abs() < 1e-9 && (pdf[1] - 0.5).abs() < 1e-9,
            "{pdf:?}"
        );
        assert_eq!(component(&[lit, barely], false).expect("weights")[1], 0.0);
    }

    #[test]
    fn the_conservative_variance_is_at_least_the_plain_variance_of_the_mean() {
        // eq. A.3 against (1/N^2) sum (x - m)^2 for random sample sets, and above it by the
        // 3 sqrt(V) term where that matters: few samples.
        let mut rng = fenestra_core::Rng::new(8);
        for _ in 0..200 {
            let n = 2 + (rng.next_f32() * 60.0) as usize;
            let xs: Vec<f64> = (0..n).map(|_| f64::from(rng.next_f32()).powi(3)).collect();
            let big_n = n as f64;
            let m = xs.iter().sum::<f64>() / big_n;
            let unbiased =
                xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (big_n * (big_n - 1.0));
            let sum_sq = xs.iter().map(|x| x * x).sum::<f64>();
            let s2 = conservative_variance(m, sum_sq, big_n);
            let plain = unbiased * (big_n - 1.0) / big_n;
            assert!(s2 >= plain * (1.0 - 1e-9), "{s2} < {plain}");
            if n <= 4 && m > 0.0 {
                assert!(s2 > plain, "{n} samples: {s2} not above {plain}");
            }
        }
    }
}
