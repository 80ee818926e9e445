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
//! After a render it offers maps of its work (passes, shadow rays, visible share, clusters
//! per cut, regions per pixel; the seed's Fig. 4.9 and 4.11) for a render's work maps. Direct
//! light only, as the seed; beyond it, BSDF samples weighed by MIS where a light outsizes the
//! BSDF's lobe, and one bounce on from mirrors and glass (module `bsdf_samples`).

mod block;
mod bsdf_samples;
mod budget;
mod estimate;
mod feedback;

use crate::forest::{Forest, CUT_SOLID_ANGLE};
use crate::sky::{self, SkyRegion, SKY_REGIONS};
use block::{BlockRender, BLOCK};
use budget::Budget;
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_render::control::RenderControl;
use fenestra_render::integrator::{Integrator, IntegratorError, Split, WorkMap};
use fenestra_render::options::{at_least_one, positive, OptionError, Options, Validate};
use fenestra_render::{Film, RenderScene, RenderSettings};
use rayon::prelude::*;
use std::sync::Mutex;

fenestra_render::choices! {
    /// How a pixel's pass estimates are combined.
    pub enum Combine {
        /// By inverse variance (eq. 3.3, 3.4): the seed's, least variance, but the variances
        /// come from the same samples as the estimates, so a pass that missed a bright light
        /// (low estimate, low variance) weighs more: the image comes out darker (measured in
        /// docs/manylights.md).
        InverseVariance = "inverse-variance",
        /// By shadow rays: every ray after pass 0 weighs the same, whatever pass it came in;
        /// unbiased. Pass 0, drawn uniformly over the cut to seed the statistics ("not to
        /// estimate the value of the pixel", §3.5.2), counts only for a pixel done after it.
        Samples = "samples",
    }
}

fenestra_render::choices! {
    /// Which points take BSDF samples besides light samples (beyond the seed).
    pub enum BsdfSamples {
        /// None: light samples only, and mirrors and glass show only what they see emitted (the
        /// seed).
        None = "none",
        /// Where a light of the cut subtends more than the BSDF's lobe (a polished floor
        /// under a lamp, a wall beside a large emitter); mirrors and glass show light one
        /// bounce on.
        Auto = "auto",
        /// Every BSDF that light sampling can reach; mirrors and glass as with `Auto`.
        All = "all",
    }
}

fenestra_render::choices! {
    /// Where the PDFs over a point's lights come from.
    pub enum Pdf {
        /// The seed's adaptive PDFs over light clusters (eq. 3.2).
        Adaptive = "adaptive",
        /// The seed's reference (§4.2): over single lights, in proportion to their unoccluded
        /// irradiance at the point (their bounds' importance), the same throughout; 100 rays a
        /// pass, at most 20,000 a pixel, black after 2,500 rays without a visible light.
        Irradiance = "irradiance",
    }
}

fenestra_render::options! {
    /// Iterative adaptive sampling (ias, ias_reference; seed 004).
    #[derive(Copy)]
    pub struct IasOptions in "ias", flags "ias" {
        /// Relative variance at which a pixel is done (the seed's t, §3.5.3; 1e-3 is a relative
        /// standard error of about 3%).
        pub threshold: f32 = 1e-3,
        /// Most passes per 8x8 block.
        pub max_passes: u32 = 15,
        /// Largest solid angle of a light cluster in a cut, in steradians.
        pub solid_angle: f32 = CUT_SOLID_ANGLE,
        /// How a pixel's passes are combined: samples (every shadow ray after pass 0, which only
        /// seeds the statistics, weighs the same; unbiased) or inverse-variance (the seed's eq.
        /// 3.3-3.4, every pass; slightly dark).
        pub combine: Combine = Combine::Samples,
        /// Where the PDFs over a point's lights come from: adaptive (the seed's ias) or
        /// irradiance (the seed's reference, as ias_reference sets it).
        pub pdf: Pdf = Pdf::Adaptive,
        /// Regions an environment is cut into, each a cluster of the cuts (the seed's 300; 0
        /// takes the environment whole).
        pub sky_regions: usize = SKY_REGIONS,
        /// Most eye rays a pixel takes while what they see emitted varies (the edge of a light
        /// seen directly), until its mean is within the threshold; 0 keeps the seed's counts
        /// (25 per surface at up to 512x512, up to three surfaces).
        pub emitted_rays: u32 = EMITTED_RAYS,
        /// Which points take a BSDF sample with each light sample, the two weighed by MIS: auto
        /// (where a light of the point's cut subtends more than the BSDF's lobe: a polished floor
        /// mirroring a window, a wall beside a large emitter), all, or none (light samples only,
        /// and mirrors and glass show only what they see emitted: the seed). With auto and all,
        /// eye rays follow mirrors and glass one bounce on.
        pub bsdf_samples: BsdfSamples = BsdfSamples::Auto,
        /// Most eye-ray hits of an anti-aliasing region that its light samples take in turn, so
        /// that the region's estimate is of the whole region and not of its first hit (1: the
        /// first hit stands for the region, as the seed).
        pub region_hits: u32 = REGION_HITS,
        /// Eye rays, in units of the seed's per surface, that a pixel takes at least when a
        /// neighbour's rays saw the edge of a light and its own did not (it may hold a sliver of
        /// the light they missed); 0 leaves such pixels their own counts.
        pub edge_rays: u32 = EDGE_RAYS,
    }
}

impl IasOptions {
    /// The seed's reference estimator with these options' threshold and beyond-the-seed
    /// choices: every light its own cluster, PDFs by unoccluded irradiance, every ray weighing
    /// the same.
    pub fn reference(self) -> Self {
        IasOptions {
            max_passes: REFERENCE_MAX_RAYS / REFERENCE_PASS_RAYS,
            solid_angle: f32::MIN_POSITIVE,
            combine: Combine::Samples,
            pdf: Pdf::Irradiance,
            sky_regions: 0,
            ..self
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

impl Validate for IasOptions {
    fn validate(&self) -> Result<(), OptionError> {
        positive("threshold", self.threshold)?;
        at_least_one("max_passes", self.max_passes.into())?;
        positive("solid_angle", self.solid_angle)?;
        if self.emitted_rays > block::MAX_EYE_RAYS {
            return Err(OptionError::new(
                "emitted_rays",
                format!(
                    "is at most {} (eye rays a pixel), got {}",
                    block::MAX_EYE_RAYS,
                    self.emitted_rays
                ),
            ));
        }
        // A pixel beside a light's edge takes edge_rays x the seed's eye rays a surface (25
        // at most).
        let most = block::MAX_EYE_RAYS / block::MOST_RAYS_PER_SURFACE;
        if self.edge_rays > most {
            return Err(OptionError::new(
                "edge_rays",
                format!(
                    "is at most {most} ({} eye rays a pixel), got {}",
                    block::MAX_EYE_RAYS,
                    self.edge_rays
                ),
            ));
        }
        at_least_one("region_hits", self.region_hits.into())?;
        if self.sky_regions > MAX_SKY_REGIONS {
            return Err(OptionError::new(
                "sky_regions",
                format!("is at most {MAX_SKY_REGIONS}, got {}", self.sky_regions),
            ));
        }
        Ok(())
    }
}

/// Eye rays (in units of the seed's per surface) of a pixel beside a light's edge, by default.
pub const EDGE_RAYS: u32 = 4;

/// Most eye-ray hits of a region shaded in turn, by default.
pub const REGION_HITS: u32 = 64;

/// Most eye rays a pixel takes at the edge of a light seen directly, by default.
pub const EMITTED_RAYS: u32 = 256;

/// Most environment regions (each is a cluster of every cut).
const MAX_SKY_REGIONS: usize = 4096;

/// The reference's rays per pass and its cap per pixel (§4.2, §4.6.4).
const REFERENCE_PASS_RAYS: u32 = 100;
const REFERENCE_MAX_RAYS: u32 = 20_000;

/// The `ias` integrator.
pub struct Ias {
    options: IasOptions,
    forest: Option<Forest>,
    /// The clusters outside the forest, numbered after its nodes.
    far: Vec<Far>,
    /// The last render's work maps (the seed's Fig. 4.9 and 4.11).
    maps: Mutex<Vec<WorkMap>>,
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
        options.check()?;
        Ok(Ias {
            options,
            forest: None,
            far: Vec::new(),
            maps: Mutex::new(Vec::new()),
        })
    }
}

/// The PDFs one point sampled its cut with, pass by pass (the seed's Fig. 4.10).
#[derive(Clone, Debug, PartialEq)]
pub struct PdfTrace {
    /// The clusters of the point's cut: forest nodes, and past the forest's nodes the
    /// clusters outside it (lights at infinity, sky regions).
    pub clusters: Vec<u32>,
    /// Per pass, the probability of each cluster.
    pub passes: Vec<Vec<f32>>,
}

/// A finished pixel: its estimate and variance, and what it took.
struct PixelOut {
    /// Its PDFs pass by pass, if traced.
    trace: Option<PdfTrace>,
    x: u32,
    y: u32,
    mean: [f64; 3],
    variance: [f64; 3],
    passes: u32,
    shadow_rays: u32,
    visible_rays: u32,
    regions: u32,
    clusters: f32,
}

/// What a block's render gives back.
struct BlockResult {
    pixels: Vec<PixelOut>,
    rays: RayCounters,
    passes: u64,
    shadow_rays: u64,
    cut_sizes: u64,
    points: u64,
    max_passes: u32,
}

impl Ias {
    /// The PDFs the largest region of pixel (x, y) samples its cut with, pass by pass, as a
    /// `width` x `height` render with `seed` takes them (its block is rendered alone, as
    /// every block is); `None` where the pixel sees no surface. Prepare first.
    pub fn pdf_trace(
        &self,
        scene: &RenderScene,
        width: u32,
        height: u32,
        seed: u64,
        x: u32,
        y: u32,
    ) -> Option<PdfTrace> {
        let forest = self.forest.as_ref()?;
        let block = BlockRender {
            ias: self,
            forest,
            scene,
            seed,
            width,
            height,
            threshold: self.options.threshold,
            trace: Some((x, y)),
        }
        .render(x / BLOCK * BLOCK, y / BLOCK * BLOCK);
        block.pixels.into_iter().find_map(|p| p.trace)
    }
}

impl Integrator for Ias {
    fn name(&self) -> &str {
        match self.options.pdf {
            Pdf::Adaptive => "ias",
            Pdf::Irradiance => "ias_reference",
        }
    }

    fn settings(&self) -> serde_json::Value {
        serde_json::to_value(self.options).unwrap_or_default()
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

    fn split(&self) -> Split {
        Split::BlockTiles
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
            leaf_of: Vec::new(),
        };
        let forest = self.forest.as_ref().unwrap_or(&empty);
        // A cropped film renders the blocks of its window (which split() keeps on the block
        // grid); pixels, samples and rays are the whole image's.
        let (width, height) = (film.width, film.height);
        let window = film.window;
        let (bx, by) = (width.div_ceil(BLOCK), height.div_ceil(BLOCK));
        // With a time limit every block takes the threshold that fits the time left; without, the
        // options' (module `budget`).
        let budget = settings.time_limit.map(|limit| {
            control.progress.note(
                "ias with a time limit: each block's threshold is set from what the blocks before it cost and the time left (not reproducible from run to run)",
            );
            // The limit is the rendering's, preparation on top (as the path tracers count it).
            let deadline = control.elapsed() + limit;
            let threads = rayon::current_num_threads();
            Budget::new(deadline, (bx * by) as usize, threads, self.options.threshold)
        });
        control.progress.start(Some(u64::from(bx * by)));
        let order = budget::shuffled(bx * by);
        let mut results: Vec<(u32, Option<BlockResult>)> = order
            .into_par_iter()
            .map(|b| {
                if control.cancelled() {
                    return (b, None);
                }
                let threshold = budget
                    .as_ref()
                    .map_or(self.options.threshold, Budget::threshold);
                let started = control.elapsed();
                let r = BlockRender {
                    ias: self,
                    forest,
                    scene,
                    seed: settings.seed,
                    width: window.full_width,
                    height: window.full_height,
                    threshold,
                    trace: None,
                }
                .render(window.x0 + (b % bx) * BLOCK, window.y0 + (b / bx) * BLOCK);
                if let Some(budget) = &budget {
                    let now = control.elapsed();
                    budget.finished(now - started, threshold, now);
                }
                control.progress.advance(1);
                (b, Some(r))
            })
            .collect();
        results.sort_unstable_by_key(|(b, _)| *b);
        let results: Vec<Option<BlockResult>> = results.into_iter().map(|(_, r)| r).collect();
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
        let mut maps = vec![vec![0.0f32; (width * height) as usize]; 5];
        for r in &results {
            let Some(r) = r else {
                stats.interrupted = true;
                continue;
            };
            for px in &r.pixels {
                let i = ((px.y - window.y0) * width + px.x - window.x0) as usize;
                film.pixels[i].set_estimate(px.mean, px.variance);
                maps[0][i] = px.passes as f32;
                maps[1][i] = px.shadow_rays as f32;
                maps[2][i] = px.visible_rays as f32 / px.shadow_rays.max(1) as f32;
                maps[3][i] = px.clusters;
                maps[4][i] = px.regions as f32;
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
        let names = [
            ("passes", "passes per pixel (the seed's Fig. 4.11)"),
            ("shadow-rays", "shadow rays per pixel"),
            (
                "visible",
                "share of shadow rays that reached their light (the seed's Fig. 4.9)",
            ),
            ("clusters", "clusters per cut"),
            ("regions", "anti-aliasing regions per pixel"),
        ];
        let made = names
            .into_iter()
            .zip(maps)
            .map(|((name, what), values)| WorkMap { name, what, values })
            .collect();
        if let Ok(mut m) = self.maps.lock() {
            *m = made;
        }
        if let Some([finest, coarsest]) = budget.as_ref().map(Budget::range) {
            stats
                .extra
                .insert("threshold_finest".into(), f64::from(finest));
            stats
                .extra
                .insert("threshold_coarsest".into(), f64::from(coarsest));
        }
        stats.time_s = control.elapsed();
        stats.derive_rates();
        stats
    }

    fn work_maps(&self) -> Vec<WorkMap> {
        self.maps.lock().map(|m| m.clone()).unwrap_or_default()
    }
}
