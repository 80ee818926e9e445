//! A light sampler defined outside fenestra-render plugs into the shared path loop: the
//! example of docs/architecture.md, checked to agree with the built-in samplers.

mod common;

use fenestra_builtin as builtin;
use fenestra_render::integrator::{LightNextEvent, PathOptions, PathTracer};
use fenestra_render::light::{LightContext, LightSampler};
use fenestra_render::{Integrator, RenderScene};

/// In odd 8x8 blocks, lights with an even index are picked twice as often as the others;
/// in even blocks all alike. A deliberately odd rule that reads the shading point's block:
/// any sampler that gives every light its probability, consistently in `sample` and `pmf`,
/// keeps next-event estimation unbiased.
struct Checkered {
    lights: usize,
}

impl Checkered {
    fn weight(&self, ctx: &LightContext, light: usize) -> f32 {
        if !ctx.sample.block.is_multiple_of(2) && light.is_multiple_of(2) {
            2.0
        } else {
            1.0
        }
    }
}

impl LightSampler for Checkered {
    fn sample(&self, ctx: &LightContext, u: f32) -> Option<(usize, f32)> {
        let total: f32 = (0..self.lights).map(|i| self.weight(ctx, i)).sum();
        let mut acc = 0.0;
        for i in 0..self.lights {
            acc += self.weight(ctx, i);
            if u * total < acc || i + 1 == self.lights {
                return Some((i, self.weight(ctx, i) / total));
            }
        }
        None
    }

    fn pmf(&self, ctx: &LightContext, light: usize) -> f32 {
        let total: f32 = (0..self.lights).map(|i| self.weight(ctx, i)).sum();
        if light < self.lights {
            self.weight(ctx, light) / total
        } else {
            0.0
        }
    }
}

fn af_checkered(options: PathOptions) -> impl Integrator {
    let next_event = LightNextEvent::with_sampler("checkered", |scene: &RenderScene| {
        Box::new(Checkered {
            lights: scene.lights.lights.len(),
        }) as Box<dyn LightSampler>
    });
    PathTracer::new("af_checkered", next_event, options)
}

#[test]
fn a_light_sampler_from_outside_agrees_with_power_sampling() {
    let options = PathOptions {
        max_depth: 3,
        ..Default::default()
    };
    let load = || builtin::load("kitchen-72").expect("builtin");
    let mut custom = af_checkered(options);
    assert_eq!(custom.settings()["light_selection"], "checkered");
    let (ours, _) = common::render(load(), &mut custom, 32, 64, 3);
    let (power, _) = common::render(
        load(),
        common::integrator("af_hf", options).as_mut(),
        32,
        64,
        4,
    );
    common::assert_agree(
        "kitchen-72: checkered vs power light selection",
        &ours,
        &power,
    );
}
