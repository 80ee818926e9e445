//! Ray queries (closest hit, any hit) behind one trait, with two backends: Intel Embree 3
//! (fast, default) and obvhs' compressed wide BVH (pure Rust, always compiled).

#[cfg(feature = "embree")]
mod embree;
mod obvhs;

#[cfg(feature = "embree")]
pub use embree::EmbreeError;

use crate::shape::Shape;
use crate::SceneError;
use fenestra_core::Ray;

/// The closest surface along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the ray.
    pub t: f32,
    /// Index of the shape in the scene.
    pub shape: u32,
    /// Primitive (triangle) index within the shape.
    pub prim: u32,
    /// Barycentrics of the triangle's 2nd and 3rd vertex (0 for analytic shapes).
    pub u: f32,
    /// See `u`.
    pub v: f32,
}

/// Closest-hit and any-hit ray queries over a scene's shapes (a BVH of one library or
/// another).
pub trait RayQuery: Send + Sync {
    /// Closest hit in (0, tmax).
    fn intersect(&self, ray: &Ray, tmax: f32) -> Option<Hit>;
    /// Whether anything lies in (0, tmax).
    fn occluded(&self, ray: &Ray, tmax: f32) -> bool;
    /// [`RayQuery::intersect`] of eight rays at once (a packet query where the library has
    /// one; the same hits as one ray at a time).
    fn intersect8(&self, rays: &[Ray; PACKET], tmax: [f32; PACKET]) -> [Option<Hit>; PACKET] {
        std::array::from_fn(|i| self.intersect(&rays[i], tmax[i]))
    }
    /// [`RayQuery::occluded`] of eight rays at once.
    fn occluded8(&self, rays: &[Ray; PACKET], tmax: [f32; PACKET]) -> [bool; PACKET] {
        std::array::from_fn(|i| self.occluded(&rays[i], tmax[i]))
    }
}

/// Rays per packet query.
pub const PACKET: usize = 8;

/// Which ray-query library to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// Intel Embree 3 (the default when built with the `embree` feature).
    #[cfg(feature = "embree")]
    Embree,
    /// obvhs' compressed wide BVH (pure Rust).
    Obvhs,
}

impl Default for Backend {
    fn default() -> Self {
        #[cfg(feature = "embree")]
        return Backend::Embree;
        #[cfg(not(feature = "embree"))]
        Backend::Obvhs
    }
}

/// A `--bvh` name this build cannot use.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum BackendError {
    /// Not a backend's name.
    #[error(transparent)]
    Unknown(#[from] fenestra_core::UnknownName),
    /// Embree asked for in a build without it.
    #[error("this build has no Embree support (built without the `embree` feature)")]
    NotBuilt,
}

impl std::str::FromStr for Backend {
    type Err = BackendError;
    fn from_str(s: &str) -> Result<Self, BackendError> {
        match s {
            #[cfg(feature = "embree")]
            "embree" => Ok(Backend::Embree),
            #[cfg(not(feature = "embree"))]
            "embree" => Err(BackendError::NotBuilt),
            "obvhs" => Ok(Backend::Obvhs),
            _ => Err(
                fenestra_core::UnknownName::new("ray-query backend", s, "embree or obvhs").into(),
            ),
        }
    }
}

impl Backend {
    /// Every backend this build has.
    pub fn available() -> Vec<Backend> {
        vec![
            #[cfg(feature = "embree")]
            Backend::Embree,
            Backend::Obvhs,
        ]
    }

    /// The name `--bvh` takes.
    pub fn name(self) -> &'static str {
        match self {
            #[cfg(feature = "embree")]
            Backend::Embree => "embree",
            Backend::Obvhs => "obvhs",
        }
    }

    /// The ray-query structure of `shapes`.
    pub fn build(self, shapes: &[Shape]) -> Result<Box<dyn RayQuery>, SceneError> {
        match self {
            #[cfg(feature = "embree")]
            Backend::Embree => Ok(Box::new(
                embree::EmbreeScene::new(shapes).map_err(SceneError::Accel)?,
            )),
            Backend::Obvhs => Ok(Box::new(obvhs::ObvhsScene::new(shapes))),
        }
    }
}
