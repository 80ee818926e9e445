//! Splats: what light paths bring to the pixels that see their vertices (light tracing).
//! A light path lands anywhere in the image, so its contributions do not belong to the pixel
//! whose sample traced it; a block gathers them here while it renders, and the film adds
//! every block's into its splat sums after the pass ([`Film::add_splats`](crate::Film)).
//! The sums are the film's exact fixed point, so their order does not matter: the image is
//! the same for any thread count.

use fenestra_core::Rgb;

/// One contribution: image pixel (x, y) and its value (already weighted by the pixel's
/// filter and divided by the path's density).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    /// Pixel column in the image.
    pub x: u32,
    /// Pixel row in the image (0 at the top).
    pub y: u32,
    /// What the light path brings to the pixel.
    pub value: Rgb,
}

/// A block's splats of one pass, and how many light paths it traced.
#[derive(Clone, Debug, Default)]
pub struct Splats {
    /// The contributions, in the order they were made.
    pub entries: Vec<Splat>,
    /// Light paths traced (those that brought nothing too: each pixel's estimate is the sum
    /// of its splats over the number of paths).
    pub paths: u64,
    /// The camera paths' second moment that their light shared with these light paths adds
    /// when they carry it alone, estimated from the light paths: over their splats,
    /// s^2 (2 - w) / w r / M (s the splat's value, its channels' squares averaged; w its MIS
    /// weight; r the ratio of light tracing's density to the path tracer's; M the light paths
    /// per camera sample of every pixel). For c a camera path vertex's contribution and w its
    /// share, c^2 - (c (1 - w))^2 = c^2 w (2 - w): summed over all light paths and divided
    /// by their number, it is E[c^2 w (2 - w)] per camera sample over the image's pixels,
    /// taken where light paths sample it well (lp_lt's trial of light paths).
    pub handed_moment: f64,
}

impl Splats {
    /// Adds a contribution of `value` to pixel (x, y).
    pub fn add(&mut self, x: u32, y: u32, value: Rgb) {
        self.entries.push(Splat { x, y, value });
    }

    /// Counts one more light path.
    pub fn count_path(&mut self) {
        self.paths += 1;
    }
}
