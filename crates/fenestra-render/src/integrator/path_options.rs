//! The path tracers' options: as given ([`PathConfig`], the `path` group) and as the path
//! loop takes them, resolved against the scene ([`PathOptions`]).

use crate::options::{positive, OptionError, Validate};
use fenestra_core::mis::MisHeuristic;
use fenestra_scene::RenderDefaults;

crate::choices! {
    /// How BSDF sampling and a next-event strategy are combined.
    pub enum Mis {
        /// Veach's balance heuristic.
        Balance = "balance",
        /// Veach's power heuristic, with exponent `path.beta`.
        Power = "power",
    }
}

crate::choices! {
    /// Which normals decide the side of a surface a direction lies on, where the shading
    /// normal (interpolated, bump- or normal-mapped) and the geometric one disagree.
    pub enum Sides {
        /// Both must agree, or the path ends there: no light leaks through a surface by its
        /// shading normals (Veach 1997, §5.3), at the cost of the light such paths carry.
        Both = "both",
        /// The shading normal alone: a path goes on through the surface, as pbrt-v4's path
        /// tracers do (the default of pbrt-v4 scenes).
        Shading = "shading",
    }
}

crate::choices! {
    /// The probability with which Russian roulette lets a path of throughput beta go on
    /// (at most 0.95).
    pub enum Roulette {
        /// The square root of beta's largest component, as Cycles takes it: paths whose
        /// throughput fell go on more often (more samples of the bounce light that lights
        /// the dark parts of a room, for longer paths).
        Sqrt = "sqrt",
        /// Beta's largest component, as pbrt takes it.
        Throughput = "throughput",
    }
}

crate::options! {
    /// Path tracing (hf, af_hf, lp_hf, sdrc, shrc).
    pub struct PathConfig in "path", flags "" {
        /// Maximum path length in segments from the camera to the emitter (2 = direct light
        /// only; default: the scene's).
        pub max_depth: Option<u32> = None,
        /// MIS heuristic combining BSDF sampling with the next-event strategy.
        pub mis: Mis = Mis::Power,
        /// Exponent of the power heuristic.
        pub beta: f32 = 2.0,
        /// Path length from which Russian roulette may end paths.
        pub rr_depth: u32 = 3,
        /// The probability with which Russian roulette lets a path go on: sqrt (the square
        /// root of its throughput, as Cycles; docs/performance.md measures it) or throughput (as
        /// pbrt).
        pub roulette: Roulette = Roulette::Sqrt,
        /// Which normals decide a surface's sides where the shading and geometric normals
        /// disagree: both (a path ends there; no light leaks through shading normals) or the
        /// shading normal alone (pbrt-v4's; the default of pbrt-v4 scenes).
        pub sides: Sides = Sides::Both,
    }
}

impl Validate for PathConfig {
    fn validate(&self) -> Result<(), OptionError> {
        if self.max_depth == Some(0) {
            return Err(OptionError::new(
                "max_depth",
                "must be at least 1 (1 = emitters seen directly, 2 = direct light)",
            ));
        }
        positive("beta", self.beta)
    }
}

impl PathConfig {
    /// The options as the path loop takes them, with `scene_max_depth` unless a path length
    /// was given.
    pub fn resolve(&self, scene_max_depth: u32) -> PathOptions {
        PathOptions {
            max_depth: self.max_depth.unwrap_or(scene_max_depth),
            mis: match self.mis {
                Mis::Balance => MisHeuristic::Balance,
                Mis::Power => MisHeuristic::Power { beta: self.beta },
            },
            rr_depth: self.rr_depth,
            roulette: self.roulette,
            sides: self.sides,
        }
    }
}

/// Options shared by the path tracers, resolved.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct PathOptions {
    /// Maximum path length in segments (2 = direct light only).
    pub max_depth: u32,
    /// How BSDF sampling and the next-event strategy are combined.
    pub mis: MisHeuristic,
    /// Path length from which Russian roulette may end a path.
    pub rr_depth: u32,
    /// Its probability of going on.
    pub roulette: Roulette,
    /// Which normals decide a surface's sides where they disagree.
    pub sides: Sides,
}

/// [`PathConfig`]'s defaults with the default scene's path length.
impl Default for PathOptions {
    fn default() -> Self {
        PathConfig::default().resolve(RenderDefaults::default().max_depth)
    }
}
