//! Many-light sampling (seed 004 and its baselines). The light BVH of Conty Estevez and Kulla
//! (2018), as pbrt-v4's BVHLightSampler uses it: lights clustered by position and emission
//! direction, picked at each shading point by descending the tree with probabilities from
//! each cluster's importance bound. It is a [`LightSampler`](fenestra_render::light::LightSampler)
//! usable by af_hf at every path vertex (`--light-selection bvh`). The seed's light-cluster
//! forest and its per-point cuts ([`forest`]) are what its adaptive sampler stands on
//! ([`ias`]). [`learned`] learns, from the render's own light samples, which groups of lights
//! each region of the scene actually sees (`--light-selection learned`).
#![warn(missing_docs)]

pub mod bounds;
pub mod bvh;
pub mod forest;
pub mod ias;
pub mod learned;
pub mod sky;

pub use bounds::{DirectionCone, LightBounds};
pub use bvh::LightBvh;
pub use forest::{Cluster, Forest, Sphere, CUT_SOLID_ANGLE};
pub use ias::{Ias, IasOptions, PdfTrace};
pub use learned::{LearnedLights, LearnedOptions};
