//! What every part of one block's render reads (seed 004 Fig. 3.4): the scene, the light
//! forest and the clusters outside it, the options, and the image the block belongs to.
//! The parts: the block's points from its eye rays (module `eye_rays`), its passes
//! (`passes`), light samples (`light_samples`) and BSDF samples (`bsdf_samples`).

use super::options::IasOptions;
use crate::forest::Forest;
use crate::sky::SkyRegion;
use fenestra_render::integrator::Sides;
use fenestra_render::RenderScene;

/// A cluster outside the forest: a light at infinity taken whole, or a region of an
/// environment's directions.
#[derive(Clone, Copy, Debug)]
pub(super) enum Far {
    Light(usize),
    Region(SkyRegion),
}

/// Everything a block's render reads.
pub(super) struct BlockRender<'a> {
    pub(super) options: &'a IasOptions,
    /// Which normals decide a surface's sides.
    pub(super) sides: Sides,
    pub(super) forest: &'a Forest,
    /// The clusters outside the forest, numbered after its nodes.
    pub(super) far: &'a [Far],
    pub(super) scene: &'a RenderScene,
    pub(super) seed: u64,
    /// The whole image's size (the block's pixels are the image's).
    pub(super) width: u32,
    pub(super) height: u32,
    /// The relative variance at which a pixel is done (the options' unless a time budget
    /// sets it).
    pub(super) threshold: f32,
    /// A pixel whose PDFs to keep pass by pass (the seed's Fig. 4.10).
    pub(super) trace: Option<(u32, u32)>,
}

impl BlockRender<'_> {
    /// Clusters of the cuts: the forest's nodes, then those outside it.
    pub(super) fn clusters(&self) -> usize {
        self.forest.nodes.len() + self.far.len()
    }
}
