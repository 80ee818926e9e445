//! Why relighting cannot go on: a file it reads, or a request it is given.

/// An error of the relighting library, by what it concerns; the message names the file, the
/// light or the frame at fault.
#[derive(Debug, thiserror::Error)]
pub enum RelightError {
    /// A lights file is not one (`name:LINE:COLUMN: what`, or the light at fault).
    #[error("{0}")]
    Lights(String),
    /// A precomputation folder cannot be opened.
    #[error("{0}")]
    Store(String),
    /// A frame cannot be relit: outside the sequence, its file unreadable, its scene not built.
    #[error("{0}")]
    Frame(String),
    /// A precomputed-transfer matrix cannot be made with the options given.
    #[error("{0}")]
    Prt(String),
}
