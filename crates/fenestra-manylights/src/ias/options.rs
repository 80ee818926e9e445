//! The options of iterative adaptive sampling (ias, ias_reference) and their limits.

use crate::forest::CUT_SOLID_ANGLE;
use crate::sky::{check_sky_regions, SKY_REGIONS};
use fenestra_render::options::{at_least_one, positive, OptionError, Validate};

fenestra_render::choices! {
    /// How a pixel's pass estimates are combined.
    pub enum Combine {
        /// By inverse variance (eq. 3.3, 3.4): the seed's, least variance, but the variances
        /// come from the same samples as the estimates, so a pass that missed a bright light
        /// (low estimate, low variance) weighs more: the image comes out darker (measured in
        /// docs/manylights.md).
        InverseVariance = "inverse-variance",
        /// By shadow rays: every ray after pass 0 weighs the same, whatever pass it came in;
        /// unbiased. Pass 0, drawn uniformly over the cut to seed the statistics ("not to
        /// estimate the value of the pixel", §3.5.2), counts only for a pixel done after it.
        Samples = "samples",
    }
}

fenestra_render::choices! {
    /// Which points take BSDF samples besides light samples (beyond the seed).
    pub enum BsdfSamples {
        /// None: light samples only, and mirrors and glass show only what they see emitted (the
        /// seed).
        None = "none",
        /// Where a light of the cut subtends more than the BSDF's lobe (a polished floor
        /// under a lamp, a wall beside a large emitter); mirrors and glass show light one
        /// bounce on.
        Auto = "auto",
        /// Every BSDF that light sampling can reach; mirrors and glass as with `Auto`.
        All = "all",
    }
}

fenestra_render::choices! {
    /// Where the PDFs over a point's lights come from.
    pub enum Pdf {
        /// The seed's adaptive PDFs over light clusters (eq. 3.2).
        Adaptive = "adaptive",
        /// The seed's reference (§4.2): over single lights, in proportion to their unoccluded
        /// irradiance at the point (their bounds' importance), the same throughout; 100 rays a
        /// pass, at most 20,000 a pixel, black after 2,500 rays without a visible light.
        Irradiance = "irradiance",
    }
}

fenestra_render::options! {
    /// Iterative adaptive sampling (ias, ias_reference; seed 004).
    #[derive(Copy)]
    pub struct IasOptions in "ias", flags "ias" {
        /// Relative variance at which a pixel is done (the seed's t, §3.5.3; 1e-3 is a relative
        /// standard error of about 3%).
        pub threshold: f32 = 1e-3,
        /// Most passes per 8x8 block.
        pub max_passes: u32 = 15,
        /// Largest solid angle of a light cluster in a cut, in steradians.
        pub solid_angle: f32 = CUT_SOLID_ANGLE,
        /// How a pixel's passes are combined: samples (every shadow ray after pass 0, which only
        /// seeds the statistics, weighs the same; unbiased) or inverse-variance (the seed's eq.
        /// 3.3-3.4, every pass; slightly dark).
        pub combine: Combine = Combine::Samples,
        /// Where the PDFs over a point's lights come from: adaptive (the seed's ias) or
        /// irradiance (the seed's reference, as ias_reference sets it).
        pub pdf: Pdf = Pdf::Adaptive,
        /// Regions an environment is cut into, each a cluster of the cuts (the seed's 300; 0
        /// takes the environment whole).
        pub sky_regions: usize = SKY_REGIONS,
        /// Most eye rays a pixel takes while what they see emitted varies (the edge of a light
        /// seen directly), until its mean is within the threshold; 0 keeps the seed's counts
        /// (25 per surface at up to 512x512, up to three surfaces).
        pub emitted_rays: u32 = EMITTED_RAYS,
        /// Which points take a BSDF sample with each light sample, the two weighed by MIS: auto
        /// (where a light of the point's cut subtends more than the BSDF's lobe: a polished floor
        /// mirroring a window, a wall beside a large emitter), all, or none (light samples only,
        /// and mirrors and glass show only what they see emitted: the seed). With auto and all,
        /// eye rays follow mirrors and glass one bounce on.
        pub bsdf_samples: BsdfSamples = BsdfSamples::Auto,
        /// Most eye-ray hits of an anti-aliasing region that its light samples take in turn, so
        /// that the region's estimate is of the whole region and not of its first hit (1: the
        /// first hit stands for the region, as the seed).
        pub region_hits: u32 = REGION_HITS,
        /// Eye rays, in units of the seed's per surface, that a pixel takes at least when a
        /// neighbour's rays saw the edge of a light and its own did not (it may hold a sliver of
        /// the light they missed); 0 leaves such pixels their own counts.
        pub edge_rays: u32 = EDGE_RAYS,
    }
}

impl IasOptions {
    /// The seed's reference estimator with these options' threshold and beyond-the-seed
    /// choices: every light its own cluster, PDFs by unoccluded irradiance, every ray weighing
    /// the same.
    pub fn reference(self) -> Self {
        IasOptions {
            max_passes: REFERENCE_MAX_RAYS / REFERENCE_PASS_RAYS,
            solid_angle: f32::MIN_POSITIVE,
            combine: Combine::Samples,
            pdf: Pdf::Irradiance,
            sky_regions: 0,
            ..self
        }
    }

    /// Shadow rays without a visible light after which a pixel is black (§4.6.4).
    pub(super) fn black_after(&self) -> u32 {
        match self.pdf {
            Pdf::Adaptive => 250,
            Pdf::Irradiance => 2500,
        }
    }
}

impl Validate for IasOptions {
    fn validate(&self) -> Result<(), OptionError> {
        positive("threshold", self.threshold)?;
        at_least_one("max_passes", self.max_passes.into())?;
        positive("solid_angle", self.solid_angle)?;
        if self.emitted_rays > MAX_EYE_RAYS {
            return Err(OptionError::new(
                "emitted_rays",
                format!(
                    "is at most {} (eye rays a pixel), got {}",
                    MAX_EYE_RAYS, self.emitted_rays
                ),
            ));
        }
        // A pixel beside a light's edge takes edge_rays x the seed's eye rays a surface (25
        // at most).
        let most = MAX_EYE_RAYS / MOST_RAYS_PER_SURFACE;
        if self.edge_rays > most {
            return Err(OptionError::new(
                "edge_rays",
                format!(
                    "is at most {most} ({} eye rays a pixel), got {}",
                    MAX_EYE_RAYS, self.edge_rays
                ),
            ));
        }
        at_least_one("region_hits", self.region_hits.into())?;
        check_sky_regions(self.sky_regions)
    }
}

/// Eye rays (in units of the seed's per surface) of a pixel beside a light's edge, by default.
pub const EDGE_RAYS: u32 = 4;

/// Most eye-ray hits of a region shaded in turn, by default.
pub const REGION_HITS: u32 = 64;

/// Most eye rays a pixel takes at the edge of a light seen directly, by default.
pub const EMITTED_RAYS: u32 = 256;

/// The reference's rays per pass and its cap per pixel (§4.2, §4.6.4).
pub(super) const REFERENCE_PASS_RAYS: u32 = 100;
const REFERENCE_MAX_RAYS: u32 = 20_000;

/// The most eye rays a pixel may take.
pub(super) const MAX_EYE_RAYS: u32 = 4096;

/// The most eye rays per unique surface (small images).
pub(super) const MOST_RAYS_PER_SURFACE: u32 = 25;
