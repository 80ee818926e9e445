//! Measurement for fenestra (SPEC R3): image metrics and efficiency, the per-pixel z-test
//! that shows an estimator is unbiased, content-keyed reference caching, bench suites and
//! their HTML reports. Depends on the core only; the renderer is driven as a separate process.

pub mod colormap;
pub mod hash;
pub mod metrics;
pub mod plot;
pub mod report;
pub mod run;
pub mod suite;
pub mod ztest;

pub use metrics::{efficiency, Metrics};
pub use ztest::{z_test, ZTest};

#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    #[error("image sizes differ: {0}x{1} against reference {2}x{3}")]
    SizeMismatch(usize, usize, usize, usize),
    #[error(transparent)]
    Image(#[from] fenestra_core::image::ImageError),
    #[error("{path}: {reason}")]
    File { path: String, reason: String },
}
