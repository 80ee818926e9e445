//! What the subcommands share: output files and their checks, Ctrl-C, progress bars, scene
//! arguments, the pieces of split renders and job files for distributed engines.

pub mod files;
pub mod interrupt;
pub mod job;
pub mod pieces;
pub mod progress;
pub mod scene_arg;
