//! The options of sdrc and shrc (seed 003 ch. 2): the `sdrc` and `shrc` groups.

use fenestra_render::options::{at_least_one, non_negative, positive, OptionError, Validate};

/// Largest validity radius a R_i of a record, in pixel footprints at its point (of the view
/// 256 (`footprint::REACH_SIDE`) pixels across).
pub(crate) const MAX_REACH_PX: f32 = 40.0;

fenestra_render::choices! {
    /// Whether a kind of surface takes its indirect light from a cache or from path tracing.
    pub enum CacheOrPath {
        /// From a cache.
        Cache = "cache",
        /// From path tracing.
        Path = "path",
    }
}

fenestra_render::choices! {
    /// Where the Lambertian lobe of a glossy material (Phong's and Ward's kd) takes its
    /// indirect light.
    pub enum LambertianLobe {
        /// The glossy cache, with the glossy lobe.
        Glossy = "glossy",
        /// The irradiance cache (with `sdrc.diffuse cache`).
        Cache = "cache",
    }
}

fenestra_render::options! {
    /// Radiance caching (sdrc, shrc; seed 003 ch. 2).
    #[derive(Copy)]
    pub struct SdrcOptions in "sdrc", flags "sdrc" {
        /// Maximum interpolation error a of SDRC records when they are placed (eq. 2.1;
        /// smaller: more records); the render passes use a x a_scale.
        pub a: f32 = 0.22,
        /// Factor on a in the render passes (the seed's 1.3: smoother interpolation).
        pub a_scale: f32 = 1.3,
        /// Rays traced to create a record (the seed's N).
        pub n: u32 = 256,
        /// BRDF-sampled directions per shading point (the seed's M; it took N ~ 12 M with 4
        /// samples per pixel, fenestra takes more samples and fewer directions each).
        pub m: u32 = 2,
        /// Largest radius of a directional query in the paraboloid disc (the seed's r_max).
        pub r_max: f32 = 0.15,
        /// Samples of a record a directional query expects at the least: its radius shrinks as
        /// a pixel averages more directions, down to the radius that holds this many of the
        /// record's N (0: it shrinks on, each query then finding one sample or none).
        pub query_samples: f32 = 5.0,
        /// Smallest reach of a record, in pixels at its point of the view 256 pixels across
        /// (larger images scale it with their larger side: 10 pixels at 640x360, 20 at
        /// 1280x720, so records resolve the same scene detail at any size; 0: as small as eq.
        /// 2.2 makes it).
        pub min_reach: f32 = 4.0,
        /// Indirect light on diffuse surfaces: cache (an irradiance cache with gradients, as
        /// the seed) or path (path tracing, as af_hf).
        pub diffuse: CacheOrPath = CacheOrPath::Cache,
        /// Indirect light on glossy surfaces: cache (sdrc's directional cache; shrc's SH
        /// cache) or path (path tracing by BSDF sampling with everything else as sdrc: the
        /// seed's Monte Carlo baseline; sdrc only).
        pub glossy: CacheOrPath = CacheOrPath::Cache,
        /// Rays per irradiance-cache record (stratified over rings and sectors).
        pub irradiance_rays: u32 = 1024,
        /// Gradients that extrapolate irradiance records: none, rotation, or both (rotation
        /// and translation; the translation gradient of path-traced radiance is mostly noise).
        pub irradiance_gradients: Gradients = Gradients::Rotation,
        /// Maximum interpolation error of the irradiance cache (Ward's a).
        pub irradiance_a: f32 = 0.15,
        /// Where the Lambertian lobe of a glossy material (Phong's and Ward's kd) takes its
        /// indirect light: glossy (the glossy cache, with the glossy lobe) or cache (the
        /// irradiance cache, with sdrc.diffuse cache; docs/sdrc.md measures both).
        pub lambertian_lobe: LambertianLobe = LambertianLobe::Glossy,
        /// Photons emitted for the light beyond the records' rays, which then end at diffuse
        /// surfaces in a photon-map estimate (the seed's setting); 0: their paths are traced
        /// on.
        pub photons: u32 = 0,
        /// Photons per radiance estimate (the k nearest).
        pub photon_k: u32 = 50,
        /// Largest photon gather radius, as a fraction of the scene's bounding-sphere radius.
        pub photon_radius: f32 = 0.03,
    }
}

impl Validate for SdrcOptions {
    fn validate(&self) -> Result<(), OptionError> {
        positive("a", self.a)?;
        positive("irradiance_a", self.irradiance_a)?;
        if !(self.a_scale >= 1.0 && self.a_scale.is_finite()) {
            return Err(OptionError::new(
                "a_scale",
                format!("must be at least 1, got {}", self.a_scale),
            ));
        }
        at_least_one("n", self.n.into())?;
        at_least_one("m", self.m.into())?;
        if self.irradiance_rays < 6 {
            return Err(OptionError::new(
                "irradiance_rays",
                format!(
                    "must be at least 6 (2 rings of 3 sectors), got {}",
                    self.irradiance_rays
                ),
            ));
        }
        if !(self.min_reach >= 0.0 && self.min_reach <= MAX_REACH_PX) {
            return Err(OptionError::new(
                "min_reach",
                format!(
                    "must lie in [0, {MAX_REACH_PX}] pixels, got {}",
                    self.min_reach
                ),
            ));
        }
        at_least_one("photon_k", self.photon_k.into())?;
        if !(self.photon_radius > 0.0 && self.photon_radius <= 1.0) {
            return Err(OptionError::new(
                "photon_radius",
                format!(
                    "must lie in (0, 1] (of the scene's radius), got {}",
                    self.photon_radius
                ),
            ));
        }
        if !(self.r_max > 0.0 && self.r_max <= 2.0) {
            return Err(OptionError::new(
                "r_max",
                format!(
                    "must lie in (0, 2] (the disc's diameter), got {}",
                    self.r_max
                ),
            ));
        }
        non_negative("query_samples", self.query_samples)
    }
}

fenestra_render::options! {
    /// SH radiance caching (shrc, sdrc's baseline; Krivanek et al. 2005).
    #[derive(Copy)]
    pub struct ShrcOptions in "shrc", flags "shrc" {
        /// Maximum interpolation error a of SH records (the seed's 0.25).
        pub a: f32 = 0.25,
        /// Rays per SH record, stratified uniformly over the hemisphere.
        pub rays: u32 = 1024,
    }
}

impl Validate for ShrcOptions {
    fn validate(&self) -> Result<(), OptionError> {
        positive("a", self.a)?;
        at_least_one("rays", self.rays.into())
    }
}

fenestra_render::choices! {
    /// Which gradients extrapolate irradiance from a record. The translation gradient needs
    /// smooth incoming radiance: from path-traced samples it is noise (docs/sdrc.md measures
    /// it), so by default only the rotation gradient is used.
    pub enum Gradients {
        /// Records' values as they are (Ward et al. 1988).
        None = "none",
        /// The rotation gradient (Ward and Heckbert 1992).
        Rotation = "rotation",
        /// Rotation and translation gradients; the translation gradient also limits R_i
        /// (R_i <= E / |grad E|).
        Both = "both",
    }
}
