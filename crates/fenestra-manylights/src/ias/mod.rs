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
mod block_stats;
mod bsdf_samples;
mod budget;
mod estimate;
mod eye_rays;
mod feedback;
mod light_samples;
mod options;
mod passes;
mod pixel;
mod point;

pub use options::{BsdfSamples, Combine, IasOptions, Pdf, EDGE_RAYS, EMITTED_RAYS, REGION_HITS};
pub use pixel::PdfTrace;

use crate::forest::Forest;
use crate::sky;
use block::{BlockRender, Far};
use budget::Budget;
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_render::control::RenderControl;
use fenestra_render::driver::{
    render_to_completion, BlockTask, CompletionEstimator, PixelEstimate, BLOCK_SIZE,
};
use fenestra_render::integrator::{Integrator, IntegratorError, Sides, Split, WorkMap};
use fenestra_render::options::Options;
use fenestra_render::{Film, RenderScene, RenderSettings};
use passes::BlockWork;
use std::sync::Mutex;

/// The `ias` integrator.
pub struct Ias {
    options: IasOptions,
    /// Which normals decide a surface's sides (`path.sides`).
    sides: Sides,
    forest: Option<Forest>,
    /// The clusters outside the forest, numbered after its nodes.
    far: Vec<Far>,
    /// The last render's work maps (the seed's Fig. 4.9 and 4.11).
    maps: Mutex<Vec<WorkMap>>,
}

impl Ias {
    /// `ias` with `options`.
    pub fn new(options: IasOptions) -> Result<Self, IntegratorError> {
        options.check()?;
        Ok(Ias {
            options,
            sides: Sides::Both,
            forest: None,
            far: Vec::new(),
            maps: Mutex::new(Vec::new()),
        })
    }

    /// The same, deciding a surface's sides by `sides` (both normals by default).
    pub fn with_sides(self, sides: Sides) -> Self {
        Ias { sides, ..self }
    }

    /// A block's render with `forest` for a `width` x `height` image with `seed`.
    fn block<'a>(
        &'a self,
        forest: &'a Forest,
        scene: &'a RenderScene,
        task: &BlockTask,
        threshold: f32,
    ) -> BlockRender<'a> {
        BlockRender {
            options: &self.options,
            sides: self.sides,
            forest,
            far: &self.far,
            scene,
            seed: task.seed,
            width: task.width,
            height: task.height,
            threshold,
            trace: None,
        }
    }

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
        let (x0, y0) = (x / BLOCK_SIZE * BLOCK_SIZE, y / BLOCK_SIZE * BLOCK_SIZE);
        let task = BlockTask::at(x0, y0, width, height, seed);
        let block = BlockRender {
            trace: Some((x, y)),
            ..self.block(forest, scene, &task, self.options.threshold)
        };
        block.render(&task, &mut RayCounters::default()).1.trace
    }
}

/// One render of ias: the forest, and the time budget if the render has a time limit.
struct IasRender<'a> {
    ias: &'a Ias,
    forest: &'a Forest,
    budget: Option<Budget>,
}

impl CompletionEstimator for IasRender<'_> {
    type Block = BlockWork;

    /// Shuffled, so that the first blocks done are a fair sample of the image's cost (module
    /// `budget`).
    fn order(&self, blocks: u32) -> Vec<u32> {
        budget::shuffled(blocks)
    }

    fn render_block(
        &self,
        scene: &RenderScene,
        task: &BlockTask,
        control: &RenderControl,
        rays: &mut RayCounters,
    ) -> (Vec<PixelEstimate>, BlockWork) {
        let threshold = self
            .budget
            .as_ref()
            .map_or(self.ias.options.threshold, Budget::threshold);
        let started = control.elapsed();
        let out = self
            .ias
            .block(self.forest, scene, task, threshold)
            .render(task, rays);
        if let Some(budget) = &self.budget {
            let now = control.elapsed();
            budget.finished(now - started, threshold, now);
        }
        out
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
                // The sun stays whole: a region would spread its samples over its cell.
                let others = others.filter(|&l| {
                    !lights.environments.contains(&l) || lights.lights[l].is_compact()
                });
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
        // With a time limit every block takes the threshold that fits the time left; without, the
        // options' (module `budget`).
        let budget = settings.time_limit.map(|limit| {
            control.progress.note(
                "ias with a time limit: each block's threshold is set from what the blocks before it cost and the time left (not reproducible from run to run)",
            );
            // The limit is the render's, preparation included (as the path tracers count it).
            let deadline = limit;
            let threads = rayon::current_num_threads();
            let blocks = film.width.div_ceil(BLOCK_SIZE) * film.height.div_ceil(BLOCK_SIZE);
            Budget::new(deadline, blocks as usize, threads, self.options.threshold)
        });
        let estimator = IasRender {
            ias: self,
            forest,
            budget,
        };
        let (mut stats, blocks) = render_to_completion(&estimator, scene, film, settings, control);
        stats.max_depth = Some(2);
        let blocks: Vec<&BlockWork> = blocks.iter().flatten().collect();
        let (width, height, window) = (film.width, film.height, film.window);
        let (mut passes, mut shadow, mut cuts, mut points) = (0u64, 0u64, 0u64, 0u64);
        let mut maps = vec![vec![0.0f32; (width * height) as usize]; 5];
        for block in &blocks {
            for px in &block.pixels {
                let Some(i) = window.index((px.x, px.y)) else {
                    continue;
                };
                maps[0][i] = px.passes as f32;
                maps[1][i] = px.shadow_rays as f32;
                maps[2][i] = px.visible_rays as f32 / px.shadow_rays.max(1) as f32;
                maps[3][i] = px.clusters;
                maps[4][i] = px.regions as f32;
                passes += u64::from(px.passes);
                shadow += u64::from(px.shadow_rays);
                stats.passes = stats.passes.max(px.passes);
            }
            cuts += block.cut_sizes;
            points += block.points;
        }
        let pixels = f64::from(width * height).max(1.0);
        let eye = stats.rays.camera as f64 / pixels;
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
        if let Some([finest, coarsest]) = estimator.budget.as_ref().map(Budget::range) {
            stats
                .extra
                .insert("threshold_finest".into(), f64::from(finest));
            stats
                .extra
                .insert("threshold_coarsest".into(), f64::from(coarsest));
        }
        stats
    }

    fn work_maps(&self) -> Vec<WorkMap> {
        self.maps.lock().map(|m| m.clone()).unwrap_or_default()
    }
}
