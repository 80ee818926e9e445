//! What can go wrong with portals: bad estimation parameters, scenes without lights or
//! openings, unreadable portal files, outputs that cannot be written.

use fenestra_core::fs::WriteError;
use std::path::PathBuf;

/// An error of portal estimation, portal files or lp_hf.
#[derive(Debug, thiserror::Error)]
pub enum PortalError {
    /// An estimation parameter is out of range.
    #[error("{0}")]
    Parameters(String),
    /// Photons need a light to start from.
    #[error("the scene has no light to trace photons from")]
    NoLight,
    /// An integrator that needs portals (named) was given none.
    #[error("{0} needs light portals and the scene has none")]
    NoPortals(&'static str),
    /// A portals.json file is unreadable or describes an invalid portal.
    #[error("{}: {reason}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// The picture could not be drawn.
    #[error("cannot draw the portal picture: {0}")]
    Plot(String),
    /// An output could not be written.
    #[error(transparent)]
    Write(#[from] WriteError),
}

impl From<PortalError> for fenestra_render::IntegratorError {
    fn from(e: PortalError) -> Self {
        fenestra_render::IntegratorError::Prepare(Box::new(e))
    }
}
