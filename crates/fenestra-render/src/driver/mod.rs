//! The render drivers: they turn an estimator into a parallel, interruptible render whose
//! pixels do not depend on the number of threads. Sample `i` of pixel `p` always uses the
//! stream (seed, p, i) and a pixel's samples are added in index order, whatever the pass
//! schedule.
//!
//! - [`passes`]: the block/pass driver. The image is cut into 8x8 pixel blocks (seed 004
//!   §3.3.2) and rendered in passes; the estimator says how many samples each pixel takes
//!   in a pass, gathers statistics per block, and sees them all between passes.
//! - [`progressive`]: the per-path driver, for estimators that only map a camera ray to
//!   radiance: passes of 1, 2, 4, ... 32 samples per pixel until the sample count or the
//!   time limit is reached. It runs on the block/pass driver.
//! - [`completion`]: the block-to-completion driver, for estimators that run each block's
//!   passes on their own (seed 004 §3.3.2): it hands out the blocks and collects their
//!   pixels.

pub mod completion;
pub mod passes;
pub mod progressive;

pub use completion::{render_to_completion, BlockTask, CompletionEstimator, PixelEstimate};
pub use passes::{render_passes, PassEstimator, PassInfo, PixelState};
pub use progressive::{next_pass_size, render_progressive, Budget, PathEstimator};

/// Side of the square pixel blocks that block/pass estimators gather statistics over.
pub const BLOCK_SIZE: u32 = 8;

/// The 8x8 block grid over a `width` x `height` image (blocks at the right and bottom edges
/// may be partial).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Blocks {
    /// Blocks per row.
    pub columns: u32,
    /// Rows of blocks.
    pub rows: u32,
}

impl Blocks {
    /// The grid over an image of the given size.
    pub fn new(width: u32, height: u32) -> Self {
        Blocks {
            columns: width.div_ceil(BLOCK_SIZE),
            rows: height.div_ceil(BLOCK_SIZE),
        }
    }

    /// Number of blocks.
    pub fn count(&self) -> usize {
        self.columns as usize * self.rows as usize
    }

    /// The block of pixel (x, y).
    pub fn of(&self, x: u32, y: u32) -> u32 {
        (y / BLOCK_SIZE) * self.columns + x / BLOCK_SIZE
    }
}
