//! A light sampler defined outside fenestra-render plugs into the shared path loop: the
//! example of docs/architecture.md, checked to agree with the built-in samplers.

mod common;

use fenestra_builtin as builtin;
use fenestra_core::{Rgb, Vec3};
use fenestra_render::integrator::{af_hf, LightNextEvent, PathOptions, PathTracer};
use fenestra_render::light::{LightContext, LightSampler, LightSelection};
use fenestra_render::{Integrator, RenderScene};
use fenestra_scene::light::Emission;
use fenestra_scene::material;
use fenestra_scene::{Camera, Material, RenderDefaults, SceneDesc, Shape, ShapeKind, TriangleMesh};

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

/// A polished floor (Phong, exponent 200) mirroring a panel of 4 x 6 emitting tiles just
/// above it: BSDF samples find the tiles often, so MIS needs each tile's pick probability.
fn polished_floor_under_tiles() -> SceneDesc {
    let floor = TriangleMesh::quad(Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 2.0);
    let mut shapes = vec![Shape::new(ShapeKind::Mesh(floor), 0)];
    for i in 0..4 {
        for k in 0..6 {
            let c = Vec3::new(-0.6 + 0.4 * i as f32, 0.6, 0.1 + 0.2 * k as f32);
            let tile = TriangleMesh::quad(c, Vec3::X * 0.2, Vec3::Z * 0.1);
            let glow = Emission::radiance(Rgb::splat(1.0 + (i * 6 + k) as f32 * 0.2));
            shapes.push(Shape::new(ShapeKind::Mesh(tile), 0).emitting(glow));
        }
    }
    SceneDesc {
        name: "polished floor under tiles".into(),
        shapes,
        materials: vec![Material::Phong(material::Phong {
            diffuse: Rgb::splat(0.1),
            specular: Rgb::splat(0.6),
            exponent: 200.0,
        })],
        lights: Vec::new(),
        camera: Camera::look_at(
            Vec3::new(0.0, -1.5, 0.6),
            Vec3::new(0.0, 0.6, 0.2),
            Vec3::Z,
            60.0,
        )
        .expect("camera"),
        defaults: RenderDefaults::default(),
        portals: Vec::new(),
    }
}

/// A sample of every light per estimate agrees with one light picked by power: on the chess
/// set (five spots and a sky, one sample each) and on a polished floor under 24 emitting
/// tiles (eight groups of about equal power, one tile of each).
#[test]
fn sampling_every_light_agrees_with_power_sampling() {
    let options = PathOptions {
        max_depth: 2,
        ..Default::default()
    };
    type Load = fn() -> SceneDesc;
    let scenes: [(&str, Load); 2] = [
        ("chess", || builtin::load("chess").expect("builtin")),
        ("polished floor under tiles", polished_floor_under_tiles),
    ];
    for (name, load) in scenes {
        let (all, _) = common::render(load(), &mut af_hf(options, LightSelection::All), 32, 32, 5);
        let (power, _) = common::render(
            load(),
            common::integrator("af_hf", options).as_mut(),
            32,
            128,
            6,
        );
        common::assert_agree(
            &format!("{name}: all vs power light selection"),
            &all,
            &power,
        );
    }
}
