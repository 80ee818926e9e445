//! Scene model of fenestra: geometry (triangle meshes, spheres, disks), materials and lights as
//! data, the pinhole camera, ray queries behind one trait with two backends (Embree, obvhs),
//! and the built-in experiment scenes.
#![warn(missing_docs)]

pub mod accel;
pub mod builtin;
pub mod camera;
mod compressed;
pub mod filter;
pub mod interaction;
pub mod light;
pub mod material;
pub mod mesh;
pub mod pbrt;
pub mod scene;
pub mod shape;
pub mod texture;

pub use accel::{Backend, Hit, RayQuery};
pub use camera::{Camera, CameraError, FieldOfView};
pub use interaction::SurfaceInteraction;
pub use light::{Emission, EnvironmentDesc, LightDesc};
pub use material::Material;
pub use scene::{RenderDefaults, Scene, SceneDesc, SceneError};
pub use shape::{Shape, ShapeKind, TriangleMesh};
pub use texture::ImageTexture;
