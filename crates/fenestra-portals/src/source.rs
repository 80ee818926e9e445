//! Where lp_hf's portals come from: the scene, a portals.json file, or an estimate (cached
//! by scene content and parameters), as the `portals` options choose.

use crate::error::PortalError;
use crate::estimate::{EstimateParams, Model};
use crate::portal::Portals;
use fenestra_eval::hash::debug_hash;
use fenestra_eval::suite::slug;
use fenestra_render::options::{OptionError, Validate};
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
        /// Light portals: a portals.json file, or "auto" to estimate them first with the
        /// default parameters of `fenestra portals` (default: the scene's own portals).
        pub source ["portals"]: Option<String> = None,
        /// With portals auto: the shape fitted to each cluster (smallest, ellipse, rectangle
        /// or pca, as `fenestra portals` fits them).
        pub model: Model = Model::Smallest,
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
    /// The source `options` name for `scene`: a portals file is read here, before the scene
    /// is built.
    pub fn new(options: &PortalSourceOptions, scene: &SceneDesc) -> Result<Self, PortalError> {
        Ok(match options.source.as_deref() {
            None => PortalSource::Scene,
            Some("auto") => {
                let params = EstimateParams {
                    model: options.model,
                    ..EstimateParams::default()
                };
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
