//! Measurement for fenestra (SPEC R3): image metrics and efficiency, the per-pixel z-test
//! that shows an estimator is unbiased, content-keyed reference caching, bench suites and
//! their HTML reports. Depends on the core only; the renderer is driven as a separate process.
#![warn(missing_docs)]

pub mod chi2;
pub mod colormap;
pub mod metrics;
pub mod plot;
pub mod report;
pub mod run;
pub mod suite;
pub mod ztest;

pub use metrics::{efficiency, Metrics};
pub use ztest::{agreement, mean_shift, z_test, Agreement, MeanShift, ZTest};

/// What can go wrong while measuring.
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// An image and its reference differ in size: (width, height, reference width, height).
    #[error("image sizes differ: {0}x{1} against reference {2}x{3}")]
    SizeMismatch(usize, usize, usize, usize),
    /// An image holds NaN or infinite pixels, which no error can be measured against.
    #[error("the {which} has {pixels} pixels that are not finite (NaN or infinite)")]
    NonFinite {
        /// "image" or "reference".
        which: &'static str,
        /// How many.
        pixels: usize,
    },
    /// A test's parameter is out of range (a significance outside (0, 1), an empty region).
    #[error("{0}")]
    Parameter(String),
    /// An image could not be read or written.
    #[error(transparent)]
    Image(#[from] fenestra_core::image::ImageError),
    /// A file could not be written.
    #[error(transparent)]
    Write(#[from] fenestra_core::fs::WriteError),
    /// A file could not be read or created.
    #[error("{path}: {reason}")]
    File {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// A suite file is unreadable or inconsistent (the reason names line and column where
    /// it can).
    #[error("{path}: {reason}")]
    Suite {
        /// The suite file.
        path: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A renderer process failed or printed something unreadable.
    #[error("{command} failed: {reason}")]
    Run {
        /// The command, as run.
        command: String,
        /// Its status and error output, or what was wrong with its output.
        reason: String,
    },
}
