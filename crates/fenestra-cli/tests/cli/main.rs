//! The `fenestra` binary as a user meets it: outputs, determinism across thread counts,
//! clear errors (non-zero exit, no panic) for bad input, interrupted runs that keep what they
//! have, outputs that never replace inputs.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use fenestra_core::image::{read_exr_metadata, Image};
use std::path::Path;
use std::process::Command;

mod bad_input;
mod denoise;
mod interrupts;
mod outputs;
