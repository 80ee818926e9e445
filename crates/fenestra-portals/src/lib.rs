//! Automatic light portals (seed 000 ch. 4-5): photons traced from the lights with cone-beams
//! (Alg. 1) are clustered by DBSCAN (Alg. 2); each cluster gets a plane by RANSAC (Alg. 3) and,
//! in that plane, the minimum-volume covering ellipse of its inliers by Khachiyan's
//! conditional-gradient method (Alg. 4) or the PCA rectangle of §5.1. The portal model, its
//! file format and the lp_hf integrator that samples portals are here too, and light paths
//! that start at the sun and enter through the portals (the lt integrator).

#![warn(missing_docs)]

pub mod aim;
pub mod carry;
pub mod cluster;
pub mod error;
pub mod estimate;
pub mod estimate_options;
pub mod export;
pub mod fitted;
pub mod light_paths;
pub mod linalg;
pub mod lp_hf;
pub mod lt;
pub mod mvce;
pub mod photon;
pub mod pilot;
pub mod plot;
pub mod portal;
pub mod ransac;
pub mod rectangle;
pub mod snap;
pub mod source;
pub mod window;

pub use error::PortalError;
pub use estimate_options::EstimateOptions;
pub use lp_hf::{lp_hf, PortalNextEvent, PortalOptions};
pub use portal::{Portal, PortalChoice, PortalFile, PortalSampling, Portals};
pub use source::{PortalSource, PortalSourceOptions};

use fenestra_render::integrator::PathConfig;
use fenestra_render::light::LightOptions;
use fenestra_render::registry::{Group, Registry};

/// Registers this crate's integrators (lp_hf, lt).
pub fn register(registry: &mut Registry) {
    registry.integrator(
        "lp_hf",
        "path tracing that aims through windows and openings (light portals; seed 000's LP_HF)",
        vec![
            Group::of::<PathConfig>(),
            Group::of::<LightOptions>(),
            Group::of::<PortalOptions>(),
            Group::of::<PortalSourceOptions>(),
            Group::of::<EstimateOptions>(),
        ],
        |b| {
            let source = PortalSource::new(&b.options()?, &b.options()?, b.scene)
                .map_err(|e| fenestra_render::IntegratorError::Prepare(Box::new(e)))?;
            Ok(Box::new(lp_hf(
                b.path()?,
                b.options()?,
                source,
                b.next_event("lp_hf", true)?,
            )?))
        },
    );
    registry.integrator(
        "lt",
        "light tracing: paths from the sun through the portals, splatted where the camera \
         sees them (the sun's light only, from non-mirror surfaces; for checking light paths)",
        vec![
            Group::of::<PathConfig>(),
            Group::of::<PortalSourceOptions>(),
            Group::of::<EstimateOptions>(),
        ],
        |b| {
            let source = PortalSource::new(&b.options()?, &b.options()?, b.scene)
                .map_err(|e| fenestra_render::IntegratorError::Prepare(Box::new(e)))?;
            Ok(Box::new(lt::Lt::new(b.path()?, source)))
        },
    );
}
