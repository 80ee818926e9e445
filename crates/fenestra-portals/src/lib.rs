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
pub mod emission;
pub mod error;
pub mod estimate;
pub mod estimate_options;
pub mod export;
pub mod fitted;
mod light_passes;
pub mod light_paths;
pub mod linalg;
pub mod lp_hf;
pub mod lp_lt;
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
pub mod trial;
pub mod window;

pub use error::PortalError;
pub use estimate_options::EstimateOptions;
pub use lp_hf::{lp_hf, portal_path_tracer, PortalNextEvent, PortalOptions};
pub use portal::{Portal, PortalChoice, PortalFile, PortalSampling, Portals};
pub use source::{PortalSource, PortalSourceOptions};

use fenestra_render::integrator::PathConfig;
use fenestra_render::light::LightOptions;
use fenestra_render::registry::{Build, Group, Registry};
use fenestra_render::IntegratorError;

/// Registers this crate's integrators (lp_hf, lt, lp_lt).
pub fn register(registry: &mut Registry) {
    registry.integrator(
        "lp_hf",
        "path tracing that aims through windows and openings (light portals; seed 000's LP_HF)",
        portal_path_groups(),
        |b| {
            let lights = b.next_event("lp_hf", true)?;
            Ok(Box::new(lp_hf(
                b.path()?,
                b.options()?,
                source(b)?,
                lights,
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
        |b| Ok(Box::new(lt::Lt::new(b.path()?, source(b)?))),
    );
    let mut groups = portal_path_groups();
    groups.push(Group::of::<lp_lt::LightPathOptions>());
    registry.integrator(
        "lp_lt",
        "lp_hf joined by MIS to light paths from the sun through the same portals (the sun's \
         glints off glossy surfaces, light through glass)",
        groups,
        |b| {
            let lights = b.next_event("lp_lt", false)?;
            let camera = portal_path_tracer("lp_lt", b.path()?, b.options()?, source(b)?, lights)?;
            Ok(Box::new(lp_lt::LpLt::new(camera, b.options()?)?))
        },
    );
}

/// The option groups of lp_hf's path tracer.
fn portal_path_groups() -> Vec<Group> {
    vec![
        Group::of::<PathConfig>(),
        Group::of::<LightOptions>(),
        Group::of::<PortalOptions>(),
        Group::of::<PortalSourceOptions>(),
        Group::of::<EstimateOptions>(),
    ]
}

/// The portals the options of `b` ask for.
fn source(b: &Build) -> Result<PortalSource, IntegratorError> {
    PortalSource::new(&b.options()?, &b.options()?, b.scene)
        .map_err(|e| IntegratorError::Prepare(Box::new(e)))
}
