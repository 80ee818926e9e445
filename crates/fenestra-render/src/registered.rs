//! This crate's own entries of a [`Registry`]: the path tracers hf and af_hf, and the fixed
//! light samplers.

use crate::integrator::{hf, LightNextEvent, PathConfig, PathTracer};
use crate::light::{LightOptions, LightSelection};
use crate::registry::{Group, Registry};

/// Registers this crate's integrators (hf, af_hf) and light samplers (auto, power, uniform,
/// all, split).
pub fn register(registry: &mut Registry) {
    for selection in [
        LightSelection::Auto,
        LightSelection::Power,
        LightSelection::Uniform,
        LightSelection::All,
        LightSelection::Split,
    ] {
        let about = match selection {
            LightSelection::Power => "in proportion to emitted power",
            LightSelection::Uniform => "every light with the same probability",
            LightSelection::All => {
                "a sample of every light in each estimate (beyond 8 lights, of one light in each \
                 of 8 groups of about equal power)"
            }
            LightSelection::Split => {
                "a sample of each light at infinity (sky, sun, distant light) in each estimate, \
                 and one of the other lights by power"
            }
            LightSelection::Auto => {
                "the default: split where a pilot at the points the camera sees measures it \
                 more efficient, else power"
            }
        };
        registry.light_sampler(selection.as_str(), about, vec![], false, move |_| {
            Ok(LightNextEvent::new(selection))
        });
    }
    registry
        .integrator(
            "hf",
            "plain path tracing: follows the surfaces' reflection only (seed 000's HF)",
            vec![Group::of::<PathConfig>()],
            |b| Ok(Box::new(hf(b.path()?))),
        )
        .integrator(
            "af_hf",
            "path tracing that also aims at the lights, the usual default (seed 000's AF_HF)",
            vec![Group::of::<PathConfig>(), Group::of::<LightOptions>()],
            |b| {
                Ok(Box::new(PathTracer::new(
                    "af_hf",
                    b.next_event("af_hf", true)?,
                    b.path()?,
                )))
            },
        );
}
