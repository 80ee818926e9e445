//! Scene model of fenestra: geometry (triangle meshes, spheres, disks), materials and lights as
//! data, the pinhole camera, mesh files, and ray queries behind one trait with two backends
//! (Embree, obvhs). Scene files are read by fenestra-pbrt, the experiment scenes are built by
//! fenestra-builtin.
#![warn(missing_docs)]

pub mod accel;
pub mod camera;
pub mod compressed;
pub mod environment;
pub mod extent;
pub mod filter;
pub mod interaction;
pub mod light;
pub mod material;
pub mod mesh;
pub mod scene;
pub mod shape;
pub mod sky;
pub mod texture;
pub mod transform;
pub mod view;

pub use accel::{Backend, Hit, RayQuery, PACKET};
pub use camera::{Camera, CameraError, FieldOfView, Projection};
pub use interaction::SurfaceInteraction;
pub use light::{Emission, EnvironmentDesc, LightDesc};
pub use material::Material;
pub use scene::{RenderDefaults, Scene, SceneDesc, SceneError};
pub use shape::{Shape, ShapeKind, TriangleMesh};
pub use texture::{ImageTexture, RoughnessTexture};
