//! One 8x8 block rendered to completion (seed 004 Fig. 3.4): its pixels' points and cuts,
//! then passes of light samples with feedback between them.

use super::bsdf_samples::{self, cut_lookup, PassPdf};
use super::estimate::{luminance, pass_estimate, PointSums};
use super::feedback::{blend, component, guarded, normal_class, unguarded, Stat};
use super::{
    BlockResult, BsdfSamples, Combine, Far, Ias, Pdf, PdfTrace, PixelOut, REFERENCE_PASS_RAYS,
};
use crate::forest::{Forest, NO_PARENT};
use fenestra_core::stats::RayCounters;
use fenestra_core::{Ray, Rgb, Sampler, Vec2, Vec3};
use fenestra_render::bsdf::Bsdf;
use fenestra_render::light::{LightHit, LightSample};
use fenestra_render::RenderScene;
use fenestra_scene::SurfaceInteraction;

/// Side of a block.
pub(super) const BLOCK: u32 = 8;
/// The most eye rays a pixel may take.
pub(super) const MAX_EYE_RAYS: u32 = 4096;

/// The most eye rays per unique surface (small images).
pub(super) const MOST_RAYS_PER_SURFACE: u32 = 25;

/// Eye rays per unique surface in a pixel by image size (§4.6.3): 25 up to 512x512, 20 up
/// to 1024x1024, 15 beyond.
fn rays_per_surface(width: u32, height: u32) -> u32 {
    match u64::from(width) * u64::from(height) {
        0..=262_144 => MOST_RAYS_PER_SURFACE,
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

/// Where an eye ray met a surface.
pub(super) struct Shade {
    pub(super) si: SurfaceInteraction,
    pub(super) bsdf: Bsdf,
    /// Towards the eye.
    pub(super) wo: Vec3,
}

/// A point to shade: a region's eye-ray hits (its first one first), which its light samples
/// take in turn, with one cut, PDF and statistics for all.
pub(super) struct Point {
    pub(super) hits: Vec<Shade>,
    /// Normal on the eye's side.
    pub(super) n: Vec3,
    pub(super) class: usize,
    /// Share of the pixel.
    pub(super) area: f32,
    /// The clusters of its cut (forest nodes; past the forest's nodes, lights at infinity).
    pub(super) cut: Vec<u32>,
    /// The seed's reference: its PDF over the cut, the same in every pass (empty for ias).
    pub(super) irradiance: Vec<f32>,
    /// At points that take BSDF samples too (module `bsdf_samples`), the cut's clusters
    /// sorted, with their index in the cut; empty at points that sample lights only.
    pub(super) lookup: Vec<(u32, u32)>,
}

/// The index of the point of the largest region.
fn largest(points: &[Point]) -> usize {
    (0..points.len())
        .max_by(|&a, &b| points[a].area.total_cmp(&points[b].area).then(b.cmp(&a)))
        .unwrap_or(0)
}

/// One pixel of the block.
pub(super) struct PixelState {
    x: u32,
    y: u32,
    pub(super) points: Vec<Point>,
    /// What the eye rays see emitted (no shadow ray), and the variance of that mean over
    /// the eye rays, per channel.
    emitted: Rgb,
    emitted_variance: [f64; 3],
    /// Whether its eye rays saw the edge of a light.
    edge: bool,
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
    visible_rays: u32,
    done: bool,
    /// Light samples the pixel has taken (its regions' hits take them in turn).
    next_sample: u32,
    /// Its rows of the pixel statistics: node slot -> stat, per class present.
    stats: Vec<(usize, Vec<Stat>)>,
    /// For the pixel whose PDFs are traced: its largest region's PDF in each pass.
    trace: Option<Vec<Vec<f32>>>,
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

/// Sums of what a pixel's eye rays see emitted, and of its squares, per channel and in
/// luminance.
#[derive(Default)]
struct Emitted {
    sum: Rgb,
    sq: [f64; 3],
    luminance: f64,
    luminance_sq: f64,
    /// The least and the most luminance a ray saw (`None` before the first ray).
    range: Option<[f64; 2]>,
}

impl Emitted {
    fn add(&mut self, le: Rgb) {
        self.sum += le;
        for (c, v) in le.to_array().into_iter().enumerate() {
            self.sq[c] += f64::from(v) * f64::from(v);
        }
        let l = f64::from(le.luminance());
        self.luminance += l;
        self.luminance_sq += l * l;
        self.range = Some(self.range.map_or([l, l], |[lo, hi]| [lo.min(l), hi.max(l)]));
    }

    /// Whether the rays saw the edge of a light: some saw it, others saw less than half as
    /// much (a smooth sky does not count).
    fn edge(&self) -> bool {
        self.range.is_some_and(|[lo, hi]| hi > 0.0 && lo < 0.5 * hi)
    }

    /// The mean over `n` rays and the variance of that mean, per channel.
    fn mean(&self, n: u32) -> (Rgb, [f64; 3]) {
        let sums = self.sum.to_array();
        let variance = std::array::from_fn(|c| variance_of_mean(f64::from(sums[c]), self.sq[c], n));
        (self.sum * (1.0 / n as f32), variance)
    }

    /// Whether the mean luminance over `n` rays is lit but its relative variance is at
    /// least `threshold`.
    fn uncertain(&self, n: u32, threshold: f32) -> bool {
        let m = self.luminance / f64::from(n);
        let variance = variance_of_mean(self.luminance, self.luminance_sq, n);
        m > 0.0 && variance >= f64::from(threshold) * m * m
    }
}

/// The variance of the mean of `n` values from their sum and the sum of their squares.
fn variance_of_mean(sum: f64, sq: f64, n: u32) -> f64 {
    let n = f64::from(n);
    let m = sum / n;
    ((sq / n - m * m) / (n - 1.0).max(1.0)).max(0.0)
}

/// Everything a block's render reads.
pub(super) struct BlockRender<'a> {
    pub(super) ias: &'a Ias,
    pub(super) forest: &'a Forest,
    pub(super) scene: &'a RenderScene,
    pub(super) seed: u64,
    pub(super) width: u32,
    pub(super) height: u32,
    /// The relative variance at which a pixel is done (the options' unless a time budget
    /// sets it).
    pub(super) threshold: f32,
    /// A pixel whose PDFs to keep pass by pass (the seed's Fig. 4.10).
    pub(super) trace: Option<(u32, u32)>,
}

impl BlockRender<'_> {
    /// Renders the block at (x0, y0) to completion.
    pub(super) fn render(&self, x0: u32, y0: u32) -> BlockResult {
        let mut rays = RayCounters::default();
        let (x1, y1) = ((x0 + BLOCK).min(self.width), (y0 + BLOCK).min(self.height));
        let mut pixels = Vec::new();
        for y in y0..y1 {
            for x in x0..x1 {
                pixels.push(self.pixel_points((x, y), 0, &mut rays));
            }
        }
        self.beside_light_edges(&mut pixels, (x0, y0, x1, y1), &mut rays);
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
        for pass in 0..self.ias.options.max_passes {
            if pixels.iter().all(|p| p.done) {
                break;
            }
            let mut pass_block: Vec<Vec<Stat>> = vec![vec![Stat::default(); k]; 6];
            // The block's F per cluster and class, as its PDF reads them this pass.
            let block_f: Vec<Vec<Option<f64>>> = block
                .iter()
                .map(|rows| rows.iter().map(guarded).collect())
                .collect();
            for p in pixels.iter_mut().filter(|p| !p.done) {
                self.pixel_pass(p, pass, &block_f, &slot, &mut pass_block, &mut rays);
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
            let regions = p.points.len() as u32;
            let trace = p
                .trace
                .as_ref()
                .filter(|_| !p.points.is_empty())
                .map(|passes| PdfTrace {
                    clusters: p.points[largest(&p.points)].cut.clone(),
                    passes: passes.clone(),
                });
            out.push(PixelOut {
                trace,
                x: p.x,
                y: p.y,
                mean,
                variance,
                passes: p.passes,
                shadow_rays: p.shadow_rays,
                visible_rays: p.visible_rays,
                regions,
                clusters: p.points.iter().map(|q| q.area * q.cut.len() as f32).sum(),
            });
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

    /// Beyond the seed: a pixel none of whose eye rays saw the edge of a light that a
    /// neighbour's rays saw (some of them met it) may hold a sliver of that light that its
    /// own rays missed; it is traced again with `edge_rays` times the seed's eye rays (and
    /// more while they disagree, as any pixel). Neighbours outside the block (x0..x1,
    /// y0..y1) are probed with their first eye rays, so blocks stay independent.
    fn beside_light_edges(
        &self,
        pixels: &mut [PixelState],
        (x0, y0, x1, y1): (u32, u32, u32, u32),
        rays: &mut RayCounters,
    ) {
        let options = &self.ias.options;
        if options.emitted_rays == 0 || options.edge_rays == 0 {
            return;
        }
        let per_surface = rays_per_surface(self.width, self.height);
        let w = x1 - x0;
        let mut probed: Vec<(u32, u32, bool)> = Vec::new();
        let mut edge = |x: u32, y: u32, pixels: &[PixelState], rays: &mut RayCounters| {
            if (x0..x1).contains(&x) && (y0..y1).contains(&y) {
                return pixels[((y - y0) * w + (x - x0)) as usize].edge;
            }
            if let Some(&(_, _, e)) = probed.iter().find(|p| (p.0, p.1) == (x, y)) {
                return e;
            }
            let e = self.probe_edge((x, y), per_surface, rays);
            probed.push((x, y, e));
            e
        };
        let mut again = Vec::new();
        for (i, p) in pixels.iter().enumerate() {
            if p.edge {
                continue;
            }
            let near = (-1i64..=1).flat_map(|dy| (-1i64..=1).map(move |dx| (dx, dy)));
            let near = near.filter(|&d| d != (0, 0)).any(|(dx, dy)| {
                let (nx, ny) = (i64::from(p.x) + dx, i64::from(p.y) + dy);
                let inside = (0..i64::from(self.width)).contains(&nx)
                    && (0..i64::from(self.height)).contains(&ny);
                inside && edge(nx as u32, ny as u32, pixels, rays)
            });
            if near {
                again.push(i);
            }
        }
        for i in again {
            let (x, y) = (pixels[i].x, pixels[i].y);
            pixels[i] = self.pixel_points((x, y), options.edge_rays * per_surface, rays);
        }
    }

    /// Whether the first `n` eye rays of pixel (x, y), the ones its own render takes, see
    /// the edge of a light (what they see emitted directly; mirrors and glass not followed).
    fn probe_edge(&self, (x, y): (u32, u32), n: u32, rays: &mut RayCounters) -> bool {
        let scene = self.scene;
        let camera = &scene.scene.camera;
        let pixel = u64::from(y) * u64::from(self.width) + u64::from(x);
        let mut seen = Emitted::default();
        for i in 0..n {
            let mut sampler = Sampler::new(self.seed, pixel, i);
            let film = Vec2::new(x as f32, y as f32) + camera.filter.sample(sampler.next_2d());
            let ray = camera.generate_ray(film, self.width, self.height);
            rays.camera += 1;
            seen.add(match scene.scene.intersect(&ray, f32::INFINITY) {
                None => self.sky_along(ray.d),
                Some(hit) => {
                    let si = scene.scene.interaction(&ray, &hit);
                    let le = scene.lights.surface_emission(&si, ray.d);
                    le.map_or(Rgb::ZERO, |(_, le)| le)
                }
            });
        }
        seen.edge()
    }

    /// What the environments send along direction `d`.
    fn sky_along(&self, d: Vec3) -> Rgb {
        let lights = &self.scene.lights;
        let sky = lights.environments.iter();
        sky.fold(Rgb::ZERO, |acc, &e| {
            acc + lights.lights[e].le(LightHit::Escaped, d)
        })
    }

    /// Step 1 with the adaptive anti-aliasing of §3.6 and §4.6.3: eye rays through the
    /// pixel (25, 20 or 15 per unique surface by resolution, at most three surfaces' worth),
    /// grouped into sub-pixel regions: a hit joins a region of the same shape, material and
    /// plane within half the pixel's footprint radius of its first hit, else starts one.
    /// Each region is a point, its share of the rays its area, with a cut through the forest
    /// at its first hit; beyond the seed it keeps its hits (up to `region_hits`) for its
    /// light samples to take in turn. What the rays see emitted is averaged over all of them.
    pub(super) fn pixel_points(
        &self,
        (x, y): (u32, u32),
        least: u32,
        rays: &mut RayCounters,
    ) -> PixelState {
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
        let mut seen = Emitted::default();
        let options = &self.ias.options;
        let most = options.emitted_rays;
        let (mut traced, mut target, mut surfaces) = (0u32, per_surface.max(least), 0u32);
        loop {
            if traced >= target {
                // Beyond the seed: where what the rays see emitted differs from ray to ray
                // (the edge of a visible light), more rays, until its mean is within the
                // pixel threshold or the pixel has `emitted_rays`.
                if traced < most && seen.uncertain(traced, self.threshold) {
                    target = (traced + per_surface).min(most);
                } else {
                    break;
                }
            }
            let mut sampler = Sampler::new(self.seed, pixel, traced);
            traced += 1;
            // Through a point drawn from the pixel filter, as the path tracers take theirs.
            let film = Vec2::new(x as f32, y as f32) + camera.filter.sample(sampler.next_2d());
            let ray = camera.generate_ray(film, self.width, self.height);
            rays.camera += 1;
            let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
                seen.add(self.sky_along(ray.d));
                continue;
            };
            let si = scene.scene.interaction(&ray, &hit);
            let material = scene.scene.shapes[si.shape].material;
            let n = if si.ng.dot(ray.d) <= 0.0 {
                si.ng
            } else {
                -si.ng
            };
            let bsdf = scene.bsdf_at(&si);
            let mut le = scene
                .lights
                .surface_emission(&si, ray.d)
                .map_or(Rgb::ZERO, |(_, le)| le);
            if options.bsdf_samples != BsdfSamples::None && bsdf.is_delta() {
                // Beyond the seed: what a mirror or glass shows one bounce on.
                le += self.specular_emission(&si, &bsdf, (-ray.d, n), &mut sampler, rays);
            }
            seen.add(le);
            let same_surface = |r: &Region| {
                r.shape == si.shape
                    && r.material == material
                    && r.point.n.dot(n) > 0.999
                    && (si.p - r.point.hits[0].si.p).dot(r.point.n).abs() <= 1e-4 * (1.0 + hit.t)
            };
            if !regions.iter().any(same_surface) {
                surfaces += 1;
                target = target.max(per_surface * surfaces.min(3));
            }
            if let Some(r) = regions
                .iter_mut()
                .find(|r| same_surface(r) && (si.p - r.point.hits[0].si.p).length() <= r.radius)
            {
                r.rays += 1;
                // Beyond the seed: the region's light samples go to its hits in turn.
                if r.point.hits.len() < options.region_hits as usize {
                    r.point.hits.push(Shade {
                        si,
                        bsdf: bsdf.into_owned(),
                        wo: -ray.d,
                    });
                }
                continue;
            }
            let bsdf = bsdf.into_owned();
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
            let lookup =
                if self.takes_bsdf_samples((&si, &bsdf, -ray.d), &cut, options.bsdf_samples) {
                    cut_lookup(&cut)
                } else {
                    Vec::new()
                };
            regions.push(Region {
                shape: si.shape,
                material,
                radius: 0.5 * hit.t * pixel_angle,
                rays: 1,
                point: Point {
                    hits: vec![Shade {
                        si,
                        bsdf,
                        wo: -ray.d,
                    }],
                    n,
                    class: normal_class(n),
                    area: 0.0,
                    cut,
                    irradiance: Vec::new(),
                    lookup,
                },
            });
        }
        let share = 1.0 / traced as f32;
        let (mean, emitted_variance) = seen.mean(traced);
        let mut points: Vec<Point> = regions
            .into_iter()
            // Mirrors and glass get no light samples (the seed's scope): only what is seen
            // emitted there, and one bounce on (module `bsdf_samples`), counts.
            .filter(|r| !r.point.cut.is_empty())
            .map(|r| Point {
                area: r.rays as f32 * share,
                ..r.point
            })
            .collect();
        if options.pdf == Pdf::Irradiance {
            for q in &mut points {
                q.irradiance = self.irradiance_pdf(q);
            }
        }
        PixelState {
            x,
            y,
            done: points.is_empty(),
            points,
            emitted: mean,
            emitted_variance,
            edge: seen.edge(),
            weight: 0.0,
            weighted: [0.0; 3],
            variance: 0.0,
            channel_variance: [0.0; 3],
            passes: 0,
            shadow_rays: 0,
            rays_before: 0,
            seen_light: false,
            visible_rays: 0,
            next_sample: 0,
            stats: Vec::new(),
            trace: (self.trace == Some((x, y))).then(Vec::new),
        }
    }

    /// One pass of one pixel (Steps 2-3): PDFs, samples, statistics, the pass estimate and
    /// its combination with the earlier passes, termination.
    #[allow(clippy::too_many_arguments)]
    fn pixel_pass(
        &self,
        p: &mut PixelState,
        pass: u32,
        block_f: &[Vec<Option<f64>>],
        slot: &[u32],
        pass_block: &mut [Vec<Stat>],
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
        // Pass 0 only seeds the statistics (§3.5.2): under its uniform PDF a pixel beside a
        // bright light most often misses it, and its estimate, counted at its share of the
        // rays, pulled such pixels down by a quarter. With shared weights it is dropped once
        // a pass that learned from it is drawn; a pixel done after pass 0 keeps it.
        if pass == 1 && options.combine == Combine::Samples {
            p.weight = 0.0;
            p.weighted = [0.0; 3];
            p.variance = 0.0;
            p.channel_variance = [0.0; 3];
        }
        let pdfs: Vec<Vec<f32>> = (0..p.points.len())
            .map(|i| self.point_pdf(&p.points[i], p, pass, block_f, slot))
            .collect();
        if let Some(trace) = &mut p.trace {
            trace.push(pdfs[largest(&p.points)].clone());
        }
        let cdfs: Vec<Vec<f32>> = pdfs
            .iter()
            .map(|pdf| {
                pdf.iter()
                    .scan(0.0f32, |acc, &w| {
                        *acc += w;
                        Some(*acc)
                    })
                    .collect()
            })
            .collect();
        let pixel_index = u64::from(p.y) * u64::from(self.width) + u64::from(p.x);
        // Each pass draws from a stream of its own (the eye rays' is stream 0): the pass's
        // PDFs were learned from the earlier passes' samples, which the pass's samples must
        // not be stratified against (Sampler::in_stream).
        let first = p.next_sample;
        let mut drawn = 0u32;
        let mut round = budget;
        loop {
            for (i, q) in p.points.iter().enumerate() {
                let cdf = &cdfs[i];
                // No light can reach the point (the reference's PDF may say so exactly).
                if cdf.last().is_none_or(|&total| total <= 0.0) {
                    continue;
                }
                let n = ((round as f32 * q.area).round() as u32).max(1);
                for _ in 0..n {
                    let index = p.next_sample.wrapping_sub(first);
                    let mut sampler = Sampler::in_stream(self.seed, pass + 1, pixel_index, index);
                    let at = &q.hits[p.next_sample as usize % q.hits.len()];
                    p.next_sample = p.next_sample.wrapping_add(1);
                    let s = self.sample(q, at, &pdfs[i], cdf, &mut sampler, rays);
                    p.shadow_rays += 1;
                    p.seen_light |= s.visible;
                    p.visible_rays += u32::from(s.visible);
                    let bsdf = if q.lookup.is_empty() {
                        Rgb::ZERO
                    } else {
                        let pass = PassPdf {
                            pdf: &pdfs[i],
                            total: cdf[cdf.len() - 1],
                        };
                        self.bsdf_sample(q, at, pass, &mut sampler, rays)
                    };
                    p.seen_light |= !bsdf.is_black();
                    sums[i].add(s.value + bsdf);
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
            let t = f64::from(self.threshold);
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
        let converged = m > 0.0 && var / (m * m) < f64::from(self.threshold);
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
        block_f: &[Vec<Option<f64>>],
        slot: &[u32],
    ) -> Vec<f32> {
        if self.ias.options.pdf == Pdf::Irradiance {
            return q.irradiance.clone();
        }
        let block = &block_f[q.class];
        let pixel = p.stats.iter().find(|(c, _)| *c == q.class);
        blend(
            q.cut.len(),
            pass,
            component(q.cut.iter().map(|&c| block[slot[c as usize] as usize])),
            pixel.and_then(|(_, s)| {
                component(
                    q.cut
                        .iter()
                        .map(|&c| unguarded(&s[slot[c as usize] as usize])),
                )
            }),
        )
    }

    /// The reference's PDF over a point's lights (§4.2): in proportion to each light's
    /// unoccluded irradiance bound at the point; lights at infinity, whose irradiance the
    /// bounds do not give, share the probability of one more light with the rest.
    fn irradiance_pdf(&self, q: &Point) -> Vec<f32> {
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
        if !at.bsdf.is_transmissive() && (s.wi.dot(q.n) > 0.0) != (wi.z * wo.z > 0.0) {
            return eval;
        }
        let unoccluded = at.bsdf.eval(wo, wi) * wi.z.abs() * s.li / s.pdf;
        if unoccluded.is_black() || !unoccluded.is_finite() {
            return eval;
        }
        let origin = at.si.spawn(s.wi);
        let tmax = match s.point {
            Some(y) => (y - origin).length() * (1.0 - 1e-4),
            None => f32::INFINITY,
        };
        rays.shadow += 1;
        let seen = unoccluded * scene.transmittance(Ray::new(origin, s.wi), tmax);
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

/// What one light sample gives.
pub(super) struct LightEval {
    /// Its contribution over its probability (the point's estimator).
    value: Rgb,
    /// Whether the shadow ray reached the light.
    pub(super) visible: bool,
    /// The light's node (for the statistics).
    leaf: u32,
    /// The light's own contribution estimate (luminance, occlusion included).
    contribution: f64,
    /// The light's power.
    power: f32,
    /// The sampled direction and the light technique's solid-angle density of it (0 for a
    /// Dirac light).
    pub(super) wi: Vec3,
    pub(super) density: f32,
}
