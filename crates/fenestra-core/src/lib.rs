//! Core types of fenestra: colours, rays, frames, sampling warps, deterministic sample
//! streams, MIS heuristics, piecewise-constant distributions, images, atomic file writing,
//! memory checks before large allocations, a
//! small seeded random stream, and the render statistics every tool reads.
#![warn(missing_docs)]

mod cie1931;
pub mod distribution;
pub mod frame;
pub mod fs;
pub mod hash;
pub mod image;
pub mod memory;
pub mod mis;
pub mod name;
pub mod palette;
pub mod ray;
pub mod rgb;
pub mod rng;
pub mod sampler;
pub mod spectrum;
pub mod stats;
pub mod trig;
pub mod warp;
pub mod white_balance;

pub use frame::Frame;
pub use glam::{Mat4, UVec2, Vec2, Vec3};
pub use name::UnknownName;
pub use ray::Ray;
pub use rgb::Rgb;
pub use rng::Rng;
pub use sampler::Sampler;

/// pi.
pub const PI: f32 = std::f32::consts::PI;
/// 1 / pi.
pub const INV_PI: f32 = std::f32::consts::FRAC_1_PI;
/// 1 / (2 pi).
pub const INV_2PI: f32 = 0.5 * std::f32::consts::FRAC_1_PI;
/// 1 / (4 pi).
pub const INV_4PI: f32 = 0.25 * std::f32::consts::FRAC_1_PI;
