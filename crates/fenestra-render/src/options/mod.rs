//! Options as data. Each integrator and light sampler declares its options once, as a type
//! ([`options!`](crate::options!)) with defaults, documentation and validation, in the crate
//! that owns it; a [`Params`] map sets them by key (`sdrc.a`), and the
//! [`Registry`](crate::registry::Registry) builds integrators from one. Command-line flags,
//! bench files and scene files are mapped onto keys; no default is written anywhere else.

mod error;
mod group;
mod params;
mod value;

pub use error::{at_least_one, non_negative, positive, OptionError};
pub use group::{help_text, Field, Options, Validate};
pub use params::Params;
pub use value::{Kind, OptionValue, ValueError};
#[doc(hidden)]
pub use {serde, serde_json};
