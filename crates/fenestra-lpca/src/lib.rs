//! Local PCA for compressing large matrices of high-dimensional vectors with k clusters of
//! affine subspaces of dimension up to l (seed 003 ch. 3): Lloyd's k-means and Phillips'
//! SortMeans, random, distance-sum, k-means++ and SortMeans++ seeding, Kambhatla-Leen LPCA
//! and SortCluster-LPCA, which prunes point-subspace distances with the generalised triangle
//! inequality (eq. 3.4) and gives exactly the same assignments as LPCA. No dependency on
//! the renderer.
#![warn(missing_docs)]

pub mod classify;
pub mod data;
pub mod fit;
pub mod init;
pub mod io;
pub mod kernels;
pub mod lpca;
pub mod schedule;
pub mod subspace;
pub mod synthetic;

pub use data::Dataset;
pub use lpca::{run, Algorithm, Options, Outcome};
pub use schedule::Schedule;
pub use subspace::Subspace;

/// What can go wrong in the LPCA library.
#[derive(Debug, thiserror::Error)]
pub enum LpcaError {
    /// The data or an option is invalid.
    #[error("{0}")]
    Input(String),
    /// A file could not be read or written.
    #[error("{path}: {reason}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
}
