//! What the subcommands share: Ctrl-C, progress bars, scene
//! arguments, the pieces of split renders and job files for distributed engines (`EngineJob`).

pub mod denoise;
pub mod engine_job;
pub mod interrupt;
pub mod pieces;
pub mod progress;
pub mod scene_arg;
