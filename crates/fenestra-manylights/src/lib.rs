//! Many-light sampling (seed 004 and its baselines). The light BVH of Conty Estevez and Kulla
//! (2018), as pbrt-v4's BVHLightSampler uses it: lights clustered by position and emission
//! direction, picked at each shading point by descending the tree with probabilities from
//! each cluster's importance bound. It is a [`LightSampler`](fenestra_render::light::LightSampler)
//! usable by af_hf at every path vertex (`light.selection bvh`). The seed's light-cluster
//! forest and its per-point cuts ([`forest`]) are what its adaptive sampler stands on
//! ([`ias`]). [`learned`] learns, from the render's own light samples, which groups of lights
//! each region of the scene actually sees (`light.selection learned`).
#![warn(missing_docs)]

pub mod bounds;
pub mod bvh;
pub mod forest;
pub mod ias;
pub mod learned;
pub mod sky;

pub use bounds::{DirectionCone, LightBounds};
pub use bvh::{BvhOptions, LightBvh};
pub use forest::{Cluster, Forest, Sphere, CUT_SOLID_ANGLE};
pub use ias::{Ias, IasOptions, PdfTrace};
pub use learned::{LearnedLights, LearnedOptions};

use fenestra_render::integrator::{LightNextEvent, PathConfig};
use fenestra_render::options::{OptionError, Options};
use fenestra_render::registry::{Build, Group, Registry};

/// Registers this crate's light samplers (bvh, learned) and integrators (ias, ias_reference).
pub fn register(registry: &mut Registry) {
    registry
        .light_sampler(
            "bvh",
            "a light tree that weighs lights by their power, distance and orientation at each point",
            vec![Group::of::<BvhOptions>()],
            false,
            |b| {
                let split = b.options::<BvhOptions>()?.split;
                Ok(if split > 0.0 {
                    LightNextEvent::with_sampler(format!("bvh(split {split})"), move |s| {
                        Box::new(LightBvh::new(&s.scene, &s.lights).with_splitting(split))
                    })
                    .taking_several()
                } else {
                    LightNextEvent::with_sampler("bvh", |s| Box::new(LightBvh::new(&s.scene, &s.lights)))
                })
            },
        )
        .light_sampler(
            "learned",
            "the light tree mixed with what the first passes learn about which lights each region \
             of the scene actually sees",
            vec![Group::of::<LearnedOptions>()],
            true,
            |b| {
                Ok(learned::light_sampling(b.options::<LearnedOptions>()?))
            },
        )
        .integrator(
            "ias",
            "direct light for scenes with many lights, learnt block by block in passes until each \
             pixel is within a set noise (seed 004)",
            vec![Group::of::<IasOptions>(), Group::of::<PathConfig>()],
            |b| {
                direct_light_only(b)?;
                let sides = b.options::<PathConfig>()?.sides;
                Ok(Box::new(Ias::new(b.options()?)?.with_sides(sides)))
            },
        )
        .integrator(
            "ias_reference",
            "the reference seed 004 measures ias against: lights picked by unoccluded irradiance, \
             rays until each pixel is within ias.threshold",
            vec![Group::of::<IasOptions>(), Group::of::<PathConfig>()],
            |b| {
                direct_light_only(b)?;
                let fixed = ["max_passes", "solid_angle", "combine", "pdf", "sky_regions"];
                if let Some((key, _)) = b.params.group(IasOptions::GROUP).find(|(k, _)| fixed.contains(k)) {
                    return Err(OptionError::new(
                        format!("{}.{key}", IasOptions::GROUP),
                        "is fixed by ias_reference (the seed's reference)",
                    )
                    .into());
                }
                let sides = b.options::<PathConfig>()?.sides;
                let reference = b.options::<IasOptions>()?.reference();
                Ok(Box::new(Ias::new(reference)?.with_sides(sides)))
            },
        );
}

/// ias renders direct light: of the path options it takes only a path length of 2 (as bench
/// suites and scripts give every integrator one) and which normals decide a surface's sides,
/// and refuses the others by name.
fn direct_light_only(b: &Build) -> Result<(), OptionError> {
    for (field, _) in b.params.group(PathConfig::GROUP) {
        let key = format!("{}.{field}", PathConfig::GROUP);
        if field == "sides" {
            continue;
        }
        if field != "max_depth" {
            return Err(OptionError::new(
                key,
                "is not read by ias (direct light only)",
            ));
        }
        if let Some(depth) = b.options::<PathConfig>()?.max_depth.filter(|&d| d != 2) {
            return Err(OptionError::new(
                key,
                format!("must be 2 for ias, which renders direct light only; got {depth}"),
            ));
        }
    }
    Ok(())
}
