//! Where lp_hf's portals come from: the scene, a portals.json file, or an estimate (cached
//! by scene content and parameters), as the `portals` options choose.

use crate::aim::Surroundings;
use crate::error::PortalError;
use crate::estimate::{estimate, EstimateParams};
use crate::estimate_options::EstimateOptions;
use crate::portal::{PortalFile, Portals};
use fenestra_core::fs::slug;
use fenestra_core::hash::debug_hash;
use fenestra_render::options::{OptionError, Validate};
use fenestra_render::{IntegratorError, RenderControl, RenderScene};
use fenestra_scene::SceneDesc;
use std::path::{Path, PathBuf};

/// Where lp_hf's portals come from.
#[derive(Clone, Debug)]
pub enum PortalSource {
    /// The scene's own: pbrt-v4 "point3 portal" quads, interface-material quads, the
    /// built-in scenes' openings.
    Scene,
    /// Given, for example read from a portals.json file.
    Given(Portals),
    /// Estimated from the scene (seed 000 ch. 4) with `params` when prepared, or read from
    /// `cache`, the portals.json an earlier estimate of the same scene with the same
    /// parameters left there (and written there after estimating).
    Estimated {
        /// The pipeline's parameters.
        params: EstimateParams,
        /// The cache file for this scene and these parameters, if any.
        cache: Option<PathBuf>,
    },
}

fenestra_render::options! {
    /// Light portals: where lp_hf takes them from.
    pub struct PortalSourceOptions in "portals", flags "portal" {
        /// Light portals: a portals.json file, or "auto" to estimate them first (with the
        /// estimate options, `fenestra portals`'s defaults unless told; default: the scene's
        /// own portals).
        pub source ["portals"]: Option<String> = None,
        /// With portals auto: the folder where estimated portals are kept, by scene content
        /// and parameters, so that the next render of the same scene reads them instead of
        /// estimating again (default: $XDG_CACHE_HOME/fenestra/portals, else
        /// ~/.cache/fenestra/portals).
        pub cache: Option<PathBuf> = None,
        /// With portals auto: estimate every time and cache nothing.
        pub no_cache ["no-portal-cache"]: bool = false,
    }
}

impl Validate for PortalSourceOptions {
    fn validate(&self) -> Result<(), OptionError> {
        if self.no_cache && self.cache.is_some() {
            return Err(OptionError::new(
                "no_cache",
                "leaves nothing for portals.cache to keep",
            ));
        }
        Ok(())
    }
}

impl PortalSource {
    /// The source `options` name for `scene`, estimated with `estimate` if auto: a portals
    /// file is read here, before the scene is built.
    pub fn new(
        options: &PortalSourceOptions,
        estimate: &EstimateOptions,
        scene: &SceneDesc,
    ) -> Result<Self, PortalError> {
        Ok(match options.source.as_deref() {
            None => PortalSource::Scene,
            Some("auto") => {
                let params = estimate.params();
                let cache = options.cache_folder().map(|dir| {
                    let key = debug_hash(&(
                        scene,
                        serde_json::to_string(&params).ok(),
                        env!("CARGO_PKG_VERSION"),
                    ));
                    dir.join(format!("{}-{key:016x}.json", slug(&scene.name)))
                });
                PortalSource::Estimated { params, cache }
            }
            Some(file) => PortalSource::Given(Portals::read_json(Path::new(file))?),
        })
    }
}

/// The share of a render's time budget that photon tracing for `--portals auto` may take,
/// and the time it may take whatever the share, up to a quarter of the budget: the box with
/// a hole in its ceiling gathers 290 photons in 0.09 s and finds its portal, 43 in the 15 ms
/// of a 0.5 s budget's 3% and finds none.
const BUDGET_SHARE: f64 = 0.03;
const BUDGET_FLOOR: (f64, f64) = (0.2, 0.25);

/// Where estimated portals came from.
#[derive(Clone, Copy, Debug)]
pub enum Estimation {
    /// Estimated now.
    Made {
        /// Photons gathered.
        photons: usize,
        /// Seconds taken.
        seconds: f64,
    },
    /// Read from the cache.
    Cached,
}

/// The portals a source gave.
pub struct Sourced {
    /// The portals.
    pub portals: Portals,
    /// For an estimated source, how they were come by.
    pub estimation: Option<Estimation>,
    /// What the camera sees around it, if the estimate found out.
    pub surroundings: Option<Surroundings>,
}

impl PortalSource {
    /// The portals this source gives for `scene`, and for an estimated source how they were
    /// come by: read from the cache when it holds an estimate with the same parameters, else
    /// estimated and then cached (an estimate that found none too: it spares the next render
    /// of the scene; nothing is cached when the estimate was interrupted, or cut short by the
    /// render's time budget).
    pub fn portals(
        &self,
        scene: &RenderScene,
        control: &RenderControl,
    ) -> Result<Sourced, IntegratorError> {
        let given = |portals| Sourced {
            portals,
            estimation: None,
            surroundings: None,
        };
        let (params, cache) = match self {
            PortalSource::Scene => return Ok(given(Portals::from_quads(&scene.scene.portals))),
            PortalSource::Given(p) => return Ok(given(p.clone())),
            PortalSource::Estimated { params, cache } => (params, cache),
        };
        if let Some((path, portals)) = cache.as_deref().and_then(|c| cached(c, params)) {
            control.progress.note(&format!(
                "portals: {} from the cache {}",
                portals.portals().len(),
                path.display()
            ));
            return Ok(Sourced {
                portals,
                estimation: Some(Estimation::Cached),
                surroundings: None,
            });
        }
        // Within a time budget, photon tracing takes at most its share of it (the cache
        // keys the estimate by the parameters asked for, so an estimate that the share cut
        // short is not cached: a render with more time would read it).
        let mut within = params.clone();
        if let Some(budget) = control.time_limit {
            let (floor, floor_share) = BUDGET_FLOOR;
            let share = (BUDGET_SHARE * budget).max(floor.min(floor_share * budget));
            let limit = within.photons.time_limit.map_or(share, |t| t.min(share));
            within.photons.time_limit = Some(limit.max(f64::MIN_POSITIVE));
        }
        let e = estimate(scene, &within, control.cancel, control.progress)?;
        control.progress.note(&format!("portals: {}", e.summary()));
        let cut_short =
            e.photons.timed_out && within.photons.time_limit != params.photons.time_limit;
        // Rendered as the cache holds them (portals.json records rebuild them to within float
        // rounding), so that a render from the cache is the same.
        let file = e.file(&scene.scene.name, params);
        if let (Some(path), false) = (cache, control.cancelled() || cut_short) {
            if let Some(dir) = path.parent() {
                let _ = std::fs::create_dir_all(dir);
            }
            if let Err(why) = file.write(path) {
                control.progress.note(&format!("portals not cached: {why}"));
            }
        }
        let made = Estimation::Made {
            photons: e.photons.points.len(),
            seconds: e.timings.total(),
        };
        Ok(Sourced {
            portals: file.portals(Path::new("the estimated portals"))?,
            estimation: Some(made),
            surroundings: Some(e.surroundings),
        })
    }
}

/// The portals cached at `path` by an estimate with `params`, if there are (any other file,
/// or an estimate with other parameters, does not count).
fn cached<'a>(path: &'a Path, params: &EstimateParams) -> Option<(&'a Path, Portals)> {
    let file = PortalFile::read(path).ok()?;
    let record = file.estimation.as_ref()?;
    let same =
        serde_json::to_value(&record.parameters).ok()? == serde_json::to_value(params).ok()?;
    (same && !record.interrupted)
        .then(|| file.portals(path).ok())
        .flatten()
        .map(|p| (path, p))
}

impl PortalSourceOptions {
    /// Where estimated portals are cached, unless `no_cache`.
    fn cache_folder(&self) -> Option<PathBuf> {
        if self.no_cache {
            return None;
        }
        if let Some(dir) = &self.cache {
            return Some(dir.clone());
        }
        let base = std::env::var_os("XDG_CACHE_HOME")
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
        Some(base.join("fenestra/portals"))
    }
}
