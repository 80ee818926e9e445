//! Colours that tell categories apart in plots (matplotlib's "tab10", first eight), as 8-bit
//! sRGB: curves of a convergence plot, clusters of a portal picture.

/// The colours, in the order categories take them.
pub const CATEGORIES: [[u8; 3]; 8] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [188, 189, 34],
];

/// The colour of category `k` (repeating after eight).
pub fn category(k: usize) -> [u8; 3] {
    CATEGORIES[k % CATEGORIES.len()]
}
