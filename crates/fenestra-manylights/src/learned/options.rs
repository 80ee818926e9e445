//! The learned sampler's options: the `learned` group.

use crate::sky::{check_sky_regions, SKY_REGIONS};
use fenestra_render::options::{at_least_one, OptionError, Validate};

/// Most passes learned from (a table is kept for each).
const MAX_PASSES: u32 = 64;

fenestra_render::choices! {
    /// The distribution mixed with the learned one, which keeps every light samplable.
    pub enum Base {
        /// The light BVH.
        Bvh = "bvh",
        /// Emitted power: costs almost nothing, so that scenes with nothing to learn pay little.
        Power = "power",
    }
}

fenestra_render::choices! {
    /// How the learned sampler takes the suns (compact lights at infinity: a sun's disk, a
    /// distant light).
    pub enum Suns {
        /// Each sun in every estimate, apart from the learned pick, which then stands for the
        /// other lights (the sky's regions, the lamps): a sunlit patch's direct sun is no coin
        /// toss against the sky, for a second shadow ray per vertex where a scene has a sun.
        Split = "split",
        /// Among the lights the learned pick chooses from, as any other.
        Picked = "picked",
    }
}

fenestra_render::options! {
    /// The learned light sampler (light.selection learned).
    #[derive(Copy)]
    pub struct LearnedOptions in "learned", flags "learned" {
        /// Groups of lights (a cut through the light tree; lights at infinity come on top)
        /// whose shares each cell learns.
        pub groups: usize = 256,
        /// Light samples of the first pass per cell, on average. Cells (boxes, six normal
        /// directions each) learn which lights they see; this sets their size (the finest
        /// power-of-two division of the scene's diagonal with no fewer), which thus follows
        /// the image's resolution and what the camera sees.
        pub cell_records: u32 = 16,
        /// The share of light samples drawn from what was learned (the rest by the light tree,
        /// which keeps every light that can reach a point samplable).
        pub mix: f32 = 0.5,
        /// Passes learned from: pre-passes of 1, 2, 4, ... samples per pixel outside the image,
        /// whose samples all use what the last one learned (more passes learn more and cost
        /// their samples on top: 1 takes 1 sample per pixel, 5 take 31).
        pub passes: u32 = 1,
        /// What the rest of the light samples are drawn by where a cell has learned something:
        /// bvh (the light tree) or power (emitted power, which costs almost nothing).
        pub base: Base = Base::Bvh,
        /// Regions of directions an environment (sky or image; not the sun's disk) is cut
        /// into, each learned as a group: a cell learns which parts of the sky it sees, through
        /// windows too, and draws directions there (0: the environment is one group, sampled
        /// by its own density).
        pub sky_regions: usize = SKY_REGIONS,
        /// How the suns (a sun's disk, a distant light) are sampled: split (each in every
        /// estimate, apart from the learned pick, which stands for the other lights: a sunlit
        /// patch's direct sun is then no coin toss against the sky, for a second shadow ray
        /// per vertex) or picked (among the other lights).
        pub suns: Suns = Suns::Split,
    }
}

impl LearnedOptions {
    /// The sampler's name with its settings, as the integrator's settings record it.
    pub fn name(&self) -> String {
        format!(
            "learned(mix {}, cell records {}, groups {}, passes {}, base {:?}, sky regions {}{})",
            self.mix,
            self.cell_records,
            self.groups,
            self.passes,
            self.base,
            self.sky_regions,
            if self.suns == Suns::Split {
                ", suns split"
            } else {
                ""
            }
        )
    }
}

impl Validate for LearnedOptions {
    fn validate(&self) -> Result<(), OptionError> {
        if !(0.0..1.0).contains(&self.mix) {
            return Err(OptionError::new(
                "mix",
                format!(
                    "must be at least 0 and below 1 (the light tree keeps the rest), got {}",
                    self.mix
                ),
            ));
        }
        at_least_one("cell_records", self.cell_records.into())?;
        at_least_one("groups", self.groups as u64)?;
        check_sky_regions(self.sky_regions)?;
        if self.passes > MAX_PASSES {
            return Err(OptionError::new(
                "passes",
                format!(
                    "is at most {MAX_PASSES} (passes past the fifth take 32 samples per pixel \
                     each), got {}",
                    self.passes
                ),
            ));
        }
        Ok(())
    }
}
