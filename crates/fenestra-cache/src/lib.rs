//! Radiance caching for fenestra (seed 003 ch. 2): spatial directional radiance caching
//! (SDRC) of the first bounce of indirect light on glossy surfaces, with an irradiance cache
//! for diffuse ones, as the `sdrc` integrator; and its baseline, SH radiance caching
//! (`shrc`).
//!
//! - [`paraboloid`]: the map from the hemisphere to the disc D;
//! - [`rgbe`]: Ward's shared-exponent radiance;
//! - [`ltree`]: a record's radiance samples in a kd-tree over D;
//! - [`octree`] and [`spatial`]: the records in space, with per-block additions merged
//!   between passes;
//! - [`record`]: a record and its spatial weight;
//! - `gather`: which cache serves a shading point, and the lookups there;
//! - `kind`: what each kind of record does (one trait), `record_rays`: the rays records are
//!   made from, `directions`: a glossy point's BRDF-sampled directions, `footprint`: the
//!   camera's pixels, which bound a record's radius;
//! - `glossy`: Algorithm 1 (SDRC) at a glossy point;
//! - [`irradiance`]: the irradiance cache with gradients for diffuse points;
//! - [`sh`] and [`harmonics`]: SH radiance caching, SDRC's baseline (integrator `shrc`);
//! - [`photons`]: the photon map for light beyond the records' rays;
//! - [`sdrc`]: the integrator.

mod directions;
mod footprint;
mod gather;
mod glossy;
pub mod harmonics;
pub mod irradiance;
mod kind;
pub mod ltree;
pub mod octree;
pub mod options;
pub mod paraboloid;
pub mod photons;
pub mod record;
mod record_rays;
pub mod rgbe;
pub mod sdrc;
pub mod sh;
pub mod spatial;

pub use gather::is_glossy;
pub use gather::GlossyCache;
pub use options::{CacheOrPath, Gradients, LambertianLobe, SdrcOptions, ShrcOptions};
pub use sdrc::Sdrc;

use fenestra_render::integrator::PathConfig;
use fenestra_render::light::LightOptions;
use fenestra_render::registry::{Build, Group, Registry};

/// Registers this crate's integrators (sdrc, shrc).
pub fn register(registry: &mut Registry) {
    let groups = || {
        vec![
            Group::of::<PathConfig>(),
            Group::of::<LightOptions>(),
            Group::of::<SdrcOptions>(),
        ]
    };
    let tracing = |b: &Build, name| -> Result<_, fenestra_render::IntegratorError> {
        Ok((
            b.options::<SdrcOptions>()?,
            b.path()?,
            b.next_event(name, false)?,
        ))
    };
    registry
        .integrator(
            "sdrc",
            "af_hf with the first bounce of indirect light on glossy surfaces cached and \
             interpolated (spatial directional radiance caching, seed 003)",
            groups(),
            move |b| {
                let (options, path, lights) = tracing(b, "sdrc")?;
                Ok(Box::new(Sdrc::new(options, path, lights)?))
            },
        )
        .integrator(
            "shrc",
            "sdrc's baseline: the same, with spherical-harmonic radiance caching (order 10) on \
             glossy surfaces (Krivanek et al. 2005)",
            [groups(), vec![Group::of::<ShrcOptions>()]].concat(),
            move |b| {
                let (options, path, lights) = tracing(b, "shrc")?;
                Ok(Box::new(Sdrc::harmonics(
                    options,
                    b.options()?,
                    path,
                    lights,
                )?))
            },
        );
}
