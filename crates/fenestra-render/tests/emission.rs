//! Rays leaving lights (photon tracing) carry their lights' power: for every kind of light
//! in the built-in scenes (area emitters, spots, a distant sun, image environments), the
//! mean power of its emitted rays equals its power: the power light selection weighs it by,
//! or for environments (whose selection power takes the image's plain mean, as pbrt-v3) pi
//! r^2 times the radiance integrated over the sphere.

use fenestra_core::{warp, Sampler};
use fenestra_render::light::Light;
use fenestra_render::RenderScene;
use fenestra_scene::{Backend, Scene};

fn scene(name: &str) -> RenderScene {
    let desc = fenestra_builtin::load(name).expect("built-in scene");
    RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"))
}

#[test]
fn emitted_rays_carry_their_lights_power() {
    let mut kinds = std::collections::BTreeSet::new();
    for name in ["box-hole", "chess", "glossy-room"] {
        let scene = scene(name);
        for (i, light) in scene.lights.lights.iter().enumerate() {
            let n = 20_000u32;
            let mut sum = 0.0f64;
            for k in 0..n {
                let mut s = Sampler::new(17, i as u64, k);
                let (u_pos, u_dir) = (s.next_2d(), s.next_2d());
                if let Some(ray) = light.sample_ray(&scene.scene, u_pos, u_dir) {
                    assert!((ray.dir.length() - 1.0).abs() < 1e-4);
                    sum += ray.power.luminance() as f64;
                }
            }
            let power = match light {
                Light::Environment(e) => {
                    let r = scene.scene.bounding_sphere().1 as f64;
                    let m = 200_000u32;
                    let integral: f64 = (0..m)
                        .map(|k| {
                            let u = Sampler::new(3, 0, k).next_2d();
                            e.le(warp::square_to_uniform_sphere(u)).luminance() as f64
                        })
                        .sum::<f64>()
                        * 4.0
                        * std::f64::consts::PI
                        / m as f64;
                    std::f64::consts::PI * r * r * integral
                }
                _ => light.power(&scene.scene) as f64,
            };
            let mean = sum / n as f64;
            assert!(
                (mean - power).abs() < 0.02 * power,
                "{name} light {i}: mean ray power {mean}, power {power}"
            );
            kinds.insert(match light {
                Light::Point(_) => "point",
                Light::Spot(_) => "spot",
                Light::Distant(_) => "distant",
                Light::Area(_) => "area",
                Light::Environment(_) => "environment",
            });
        }
    }
    assert_eq!(kinds.len(), 4, "{kinds:?}");
}
