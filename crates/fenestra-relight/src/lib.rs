//! Relighting of animation sequences (seed 003 ch. 4; issue 14). What is built so far is the
//! ground the precomputation stands on:
//!
//! - [`animation`]: keyframed objects and camera (JSON) and their interpolation;
//! - [`sequence`]: a scene posed at any frame of its animation;
//! - [`neighbours`]: the nearest explored view samples in space-time (a kd-tree);
//! - [`explore`]: where to evaluate transfer: Alg. 3 with the space-time distance of eq. 4.2;
//! - [`gather`]: gather samples on the surfaces, in a balanced tree's order;
//! - [`transfer`]: transfer vectors by the N-body traversal (eq. 4.1), the gather samples'
//!   radiosity and one-bounce relighting;
//! - [`haar`]: the orthonormal Haar transform of transfer vectors (§4.5.1);
//! - [`sparse`]: sparse wavelet images and Wavelet-LPCA's classification distance (Alg. 4);
//! - [`empca`]: Roweis's EM-PCA on sparse rows, Wavelet-LPCA's subspace update (§4.5.2.2);
//! - [`wlpca`]: Wavelet-LPCA, the two together (§4.5);
//! - [`reconstruct`]: transfer at unexplored view samples from nearby ones (eq. 4.5);
//! - [`light_check`]: pixels the scene's own light shows reconstructed or compressed badly;
//! - [`frame`]: one frame precomputed (all of the above) and relit.

pub mod animation;
pub mod empca;
pub mod error;
pub mod explore;
pub mod frame;
pub mod frame_file;
pub mod gather;
pub mod haar;
pub mod image;
pub mod light_check;
pub mod lights_file;
pub mod neighbours;
pub mod player;
pub mod prt;
pub mod reconstruct;
pub mod sequence;
pub mod sparse;
pub mod store;
pub mod transfer;
pub mod wlpca;
