//! One module per subcommand: its arguments and what it runs.

pub mod bench;
pub mod compare;
pub mod lpca;
pub mod merge;
pub mod portals;
pub mod prt;
pub mod raybench;
pub mod reference;
pub mod relight;
pub mod render;
pub mod scene;
pub mod split;
