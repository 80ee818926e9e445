//! An integrator defined outside fenestra-render plugs into it: a block visualiser that
//! renders through the block/pass driver, with per-block statistics, a different number of
//! samples per pixel in each pass, its own options, and a registry entry, as a research crate
//! would.

use fenestra_builtin as builtin;
use fenestra_core::stats::{RayCounters, RenderStats};
use fenestra_core::{Rgb, Sampler};
use fenestra_render::driver::{render_passes, Blocks, PassEstimator, PassInfo, PixelState};
use fenestra_render::options::{at_least_one, OptionError, Params, Validate};
use fenestra_render::registry::{Group, Registry};
use fenestra_render::sample_context::SampleContext;
use fenestra_render::{
    render_image, Film, Integrator, IntegratorError, RenderControl, RenderScene, RenderSettings,
};
use fenestra_scene::{Backend, Scene};
use std::sync::{Arc, Mutex};

fenestra_render::options! {
    /// The block visualiser.
    #[derive(Copy)]
    pub struct BlockOptions in "blocks", flags "blocks" {
        /// Samples per pixel of the second pass (in blocks with an even index).
        pub second_pass: u32 = 2,
    }
}

impl Validate for BlockOptions {
    fn validate(&self) -> Result<(), OptionError> {
        at_least_one("second_pass", self.second_pass.into())
    }
}

/// Paints each pixel with its block's index (red), its own index (green) and the first
/// number of its sample stream (blue). Pass 0 takes one sample per pixel; pass 1 takes
/// `second_pass` more in blocks with an even index only; then it stops.
struct BlockVisualiser {
    options: BlockOptions,
    seen: Arc<Mutex<Vec<Seen>>>,
}

/// What `end_pass` saw in one pass: each block's samples and sum of sample indices.
type Seen = Vec<(u64, u64)>;

/// Statistics of one block in one pass.
struct BlockTally {
    block: u32,
    samples: u64,
    /// Sum of the sample indices taken (they continue across passes).
    indices: u64,
}

struct Passes<'a> {
    visualiser: &'a BlockVisualiser,
    blocks: usize,
}

impl PassEstimator for Passes<'_> {
    type BlockStats = BlockTally;

    fn begin_pass(&mut self, pass: &PassInfo) -> bool {
        pass.index < 2
    }

    fn block_stats(&self, block: u32, _: u32) -> BlockTally {
        BlockTally {
            block,
            samples: 0,
            indices: 0,
        }
    }

    fn samples(&self, pixel: &PixelState) -> u32 {
        match pixel.pass {
            0 => 1,
            _ if pixel.block.is_multiple_of(2) => self.visualiser.options.second_pass,
            _ => 0,
        }
    }

    fn sample(
        &self,
        _: &RenderScene,
        ctx: &SampleContext,
        sampler: &mut Sampler,
        stats: &mut BlockTally,
        _: &mut RayCounters,
    ) -> Rgb {
        assert_eq!(
            stats.block, ctx.block,
            "a block's samples go to its own statistics"
        );
        stats.samples += 1;
        stats.indices += ctx.index as u64;
        Rgb::new(ctx.block as f32, ctx.pixel() as f32, sampler.next_1d())
    }

    fn end_pass(&mut self, _: &RenderScene, _: &Film, blocks: Vec<BlockTally>) -> bool {
        assert_eq!(blocks.len(), self.blocks);
        assert!(blocks.iter().enumerate().all(|(i, b)| b.block == i as u32));
        if let Ok(mut seen) = self.visualiser.seen.lock() {
            seen.push(blocks.iter().map(|b| (b.samples, b.indices)).collect());
        }
        true
    }
}

impl Integrator for BlockVisualiser {
    fn name(&self) -> &str {
        "blocks"
    }

    fn settings(&self) -> serde_json::Value {
        serde_json::to_value(self.options).unwrap_or_default()
    }

    fn render(
        &self,
        scene: &RenderScene,
        film: &mut Film,
        settings: &RenderSettings,
        control: &RenderControl,
    ) -> RenderStats {
        let blocks = Blocks::new(film.width, film.height).count();
        let mut passes = Passes {
            visualiser: self,
            blocks,
        };
        render_passes(&mut passes, scene, film, settings, control)
    }
}

/// A registry with the visualiser, which records what it sees in `seen`.
fn registry(seen: &Arc<Mutex<Vec<Seen>>>) -> Registry {
    let seen = seen.clone();
    let mut registry = Registry::new();
    registry.integrator(
        "blocks",
        "block indices",
        vec![Group::of::<BlockOptions>()],
        move |b| {
            Ok(Box::new(BlockVisualiser {
                options: b.options()?,
                seen: seen.clone(),
            }))
        },
    );
    registry
}

/// Builds the visualiser from `params`.
fn build(params: &Params) -> Result<Box<dyn Integrator>, IntegratorError> {
    let scene = builtin::load("box-hole").expect("builtin");
    registry(&Arc::default()).build("blocks", params, &scene)
}

/// Renders box-hole with the visualiser, built by a registry as the binary builds its own;
/// returns the film, the statistics and what the visualiser saw between passes.
fn render_with(threads: usize, width: u32, height: u32) -> (Film, RenderStats, Vec<Seen>) {
    let seen = Arc::new(Mutex::new(Vec::new()));
    let desc = builtin::load("box-hole").expect("builtin");
    let mut integrator = registry(&seen)
        .build("blocks", &Params::new(), &desc)
        .expect("registered");
    let scene = RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"));
    let settings = RenderSettings {
        first_sample: 0,
        spp: 1,
        time_limit: None,
        seed: 9,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    let (film, stats) = pool
        .install(|| render_image(integrator.as_mut(), &scene, width, height, &settings))
        .expect("render");
    let seen = seen.lock().expect("lock").clone();
    (film, stats, seen)
}

#[test]
fn a_block_pass_integrator_from_another_crate_renders_through_the_driver() {
    // 20 x 12 pixels: 3 x 2 blocks, the last column and row of blocks partial.
    let (width, height) = (20u32, 12u32);
    let (film, stats, seen) = render_with(2, width, height);
    let blocks = Blocks::new(width, height);
    assert_eq!((blocks.columns, blocks.rows), (3, 2));
    assert_eq!(stats.integrator, "blocks");
    assert_eq!(stats.passes, 2);
    for y in 0..height {
        for x in 0..width {
            let p = &film.pixels[(y * width + x) as usize];
            let block = blocks.of(x, y);
            let mean = p.mean();
            assert_eq!(mean[0], block as f64, "pixel ({x}, {y}) shows its block");
            assert_eq!(mean[1], (y * width + x) as f64);
            let expected = if block.is_multiple_of(2) { 3 } else { 1 };
            assert_eq!(p.count, expected, "pixel ({x}, {y})");
        }
    }
    assert_eq!((stats.spp, stats.spp_max), (1, 3));
    // Per pass, the samples each block reported: 64 pixels in a whole block, fewer at the
    // edges (columns of 8, 8, 4 pixels; rows of 8, 4). Pass 0 takes sample 0 of every pixel,
    // pass 1 samples 1 and 2 of the pixels in even blocks.
    let area = |b: usize| [8u64, 8, 4][b % 3] * [8u64, 4][b / 3];
    assert_eq!(seen.len(), 2);
    assert_eq!(seen[0], (0..6).map(|b| (area(b), 0)).collect::<Vec<_>>());
    let second: Vec<(u64, u64)> = (0..6usize)
        .map(|b| {
            if b.is_multiple_of(2) {
                (2 * area(b), 3 * area(b))
            } else {
                (0, 0)
            }
        })
        .collect();
    assert_eq!(seen[1], second);
}

#[test]
fn block_pass_renders_do_not_depend_on_the_thread_count() {
    let sums = |threads| {
        let (film, _, _) = render_with(threads, 20, 12);
        film.pixels
    };
    assert_eq!(sums(1), sums(2));
}

#[test]
fn its_options_are_set_by_key_as_numbers_or_text_and_checked_by_name() {
    let settings = |params: &Params| build(params).expect("options").settings();
    let defaults = settings(&Params::new());
    assert_eq!(defaults, serde_json::json!({ "second_pass": 2 }));
    assert_eq!(
        settings(&Params::new().with("blocks.second_pass", 2)),
        defaults
    );
    assert_eq!(
        settings(&Params::new().with("blocks.second_pass", "2")),
        defaults
    );
    assert_eq!(
        settings(&Params::new().with("blocks.second_pass", 5))["second_pass"],
        5
    );
    let refused = |params: Params| match build(&params) {
        Ok(_) => panic!("{params:?} was accepted"),
        Err(e) => e.to_string(),
    };
    assert_eq!(
        refused(Params::new().with("blocks.second_pass", 0)),
        "blocks.second_pass must be at least 1"
    );
    assert_eq!(
        refused(Params::new().with("blocks.second_pass", "-1")),
        "blocks.second_pass takes a whole number from 0, got \"-1\""
    );
    assert_eq!(
        refused(Params::new().with("blocks.third_pass", 1)),
        "blocks.third_pass is not an option (blocks has second_pass)"
    );
    assert_eq!(
        refused(Params::new().with("sdrc.a", 0.3)),
        "sdrc.a is not an option (the groups: blocks)"
    );
}
