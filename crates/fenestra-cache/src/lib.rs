//! Radiance caching for fenestra (seed 003 ch. 2): spatial directional radiance caching
//! (SDRC) of the first bounce of indirect light on glossy surfaces, as the `sdrc` integrator.
//!
//! - [`paraboloid`]: the map from the hemisphere to the disc D;
//! - [`rgbe`]: Ward's shared-exponent radiance;
//! - [`ltree`]: a record's radiance samples in a kd-tree over D;
//! - [`octree`] and [`spatial`]: the records in space, with per-block additions merged
//!   between passes;
//! - [`record`]: a record and its spatial weight;
//! - `gather`: Algorithm 1 at one shading point;
//! - [`sdrc`]: the integrator.

mod gather;
pub mod ltree;
pub mod octree;
pub mod paraboloid;
pub mod record;
pub mod rgbe;
pub mod sdrc;
pub mod spatial;

pub use gather::is_glossy;
pub use sdrc::{Sdrc, SdrcOptions};
