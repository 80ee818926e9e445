//! Relighting of animation sequences (seed 003 ch. 4; issue 14). What is built so far is the
//! ground the precomputation stands on:
//!
//! - [`animation`]: keyframed objects and camera (JSON) and their interpolation;
//! - [`haar`]: the orthonormal Haar transform of transfer vectors (§4.5.1);
//! - [`sparse`]: sparse wavelet images and Wavelet-LPCA's classification distance (Alg. 4);
//! - [`empca`]: Roweis's EM-PCA on sparse rows, Wavelet-LPCA's subspace update (§4.5.2.2).
//! - [`wlpca`]: Wavelet-LPCA, the two together (§4.5).

pub mod animation;
pub mod empca;
pub mod haar;
pub mod sparse;
pub mod wlpca;
