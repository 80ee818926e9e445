//! Measuring from the command line: cached references, `compare`, bench suites and their
//! reports, the matrix tools (btf, lpca, prt), real scenes against their reference renders.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use fenestra_core::image::{read_exr_metadata, Image};
use std::path::{Path, PathBuf};

mod commands;
mod judged;
