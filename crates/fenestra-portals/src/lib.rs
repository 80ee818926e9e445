//! Automatic light portals (seed 000 ch. 4-5): the fitting stages of the estimation pipeline.
//! A cluster of photons gets a plane by RANSAC (Alg. 3) and, in that plane, the minimum-volume
//! covering ellipse of its inliers by Khachiyan's conditional-gradient method (Alg. 4) or the
//! PCA rectangle of §5.1.

pub mod linalg;
pub mod mvce;
pub mod ransac;
pub mod rng;
