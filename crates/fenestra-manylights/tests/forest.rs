//! The seed's light-cluster forest and cuts on the built-in many-light scenes: a cut's
//! clusters are disjoint, respect the solid-angle bound (or are single lights), and every
//! light they leave out sends nothing to the point.

use fenestra_builtin as builtin;
use fenestra_core::{Rng, Vec2, Vec3};
use fenestra_manylights::{Forest, CUT_SOLID_ANGLE};
use fenestra_render::light::Lights;
use fenestra_scene::{Backend, Scene};

#[test]
fn cuts_are_disjoint_bounded_and_leave_out_only_lights_that_cannot_reach() {
    for name in ["kitchen-72", "ponderosa-138", "terminal-832"] {
        let scene =
            Scene::build(builtin::load(name).expect("builtin"), Backend::Obvhs).expect("scene");
        let lights = Lights::new(&scene);
        let forest = Forest::new(&scene, &lights);
        // Every light but those at infinity is a leaf of exactly one tree.
        let mut all = Vec::new();
        for &root in &forest.roots {
            forest.lights_below(root, &mut all);
        }
        all.sort_unstable();
        let finite = lights.lights.len() - forest.infinite.len();
        assert_eq!(all.len(), finite, "{name}: leaves");
        all.dedup();
        assert_eq!(all.len(), finite, "{name}: a light in two trees");

        let (w, h) = (48, 27);
        let mut rng = Rng::new(7);
        let mut cut = Vec::new();
        let mut below = Vec::new();
        for _ in 0..40 {
            let px = Vec2::new(rng.next_f32() * w as f32, rng.next_f32() * h as f32);
            let ray = scene.camera.generate_ray(px, w, h);
            let Some(hit) = scene.intersect(&ray, f32::INFINITY) else {
                continue;
            };
            let si = scene.interaction(&ray, &hit);
            let n = si.ng * -si.ng.dot(ray.d).signum();
            let p = si.spawn(n);
            forest.cut(p, n, CUT_SOLID_ANGLE, &mut cut);
            let mut covered = vec![false; lights.lights.len()];
            for &c in &cut {
                let node = &forest.nodes[c as usize];
                assert!(
                    node.children.is_none() || node.sphere.solid_angle(p) <= CUT_SOLID_ANGLE,
                    "{name}: a cluster of {} sr in the cut",
                    node.sphere.solid_angle(p)
                );
                below.clear();
                forest.lights_below(c, &mut below);
                for &l in &below {
                    assert!(!covered[l as usize], "{name}: light {l} twice in a cut");
                    covered[l as usize] = true;
                }
            }
            // What the cut leaves out cannot light the point.
            for (l, light) in lights.lights.iter().enumerate() {
                if covered[l] || forest.infinite.contains(&l) {
                    continue;
                }
                for _ in 0..16 {
                    if let Some(s) = light.sample_li(&scene, p, rng.next_2d()) {
                        assert!(
                            s.li.is_black() || s.wi.dot(n) <= 1e-4,
                            "{name}: light {l} was pruned at {p} but sends {:?} from {}",
                            s.li,
                            s.wi
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn a_larger_solid_angle_bound_gives_smaller_cuts() {
    let scene = Scene::build(
        builtin::load("terminal-832").expect("builtin"),
        Backend::Obvhs,
    )
    .expect("scene");
    let forest = Forest::new(&scene, &Lights::new(&scene));
    let (p, n) = (Vec3::new(0.0, 0.0, 1.0), Vec3::Z);
    let mut sizes = Vec::new();
    let mut cut = Vec::new();
    for bound in [0.002, 0.02, 0.2, 2.0] {
        forest.cut(p, n, bound, &mut cut);
        sizes.push(cut.len());
    }
    assert!(sizes.windows(2).all(|w| w[0] >= w[1]), "{sizes:?}");
    assert!(sizes[0] > sizes[3], "{sizes:?}");
}

#[test]
fn sky_regions_tile_the_sphere_and_hold_the_skys_power() {
    use fenestra_manylights::sky::{regions, SKY_REGIONS};
    // ponderosa-138's sky: the regions cover every direction once, and their pre-integrated
    // powers add up to the sky's radiance integrated over the sphere.
    let scene = Scene::build(
        builtin::load("ponderosa-138").expect("builtin"),
        Backend::Obvhs,
    )
    .expect("scene");
    let lights = Lights::new(&scene);
    assert_eq!(lights.environments.len(), 1);
    let sky = regions(&lights, SKY_REGIONS);
    assert_eq!(sky.len(), SKY_REGIONS);
    let solid: f32 = sky.iter().map(|r| r.solid_angle()).sum();
    assert!((solid - 4.0 * std::f32::consts::PI).abs() < 1e-3, "{solid}");
    let env = &lights.lights[lights.environments[0]];
    let mut rng = Rng::new(11);
    let (n, mut integral) = (200_000, 0.0f64);
    for _ in 0..n {
        let d = fenestra_core::warp::square_to_uniform_sphere(rng.next_2d());
        let le = env
            .le(fenestra_render::light::LightHit::Escaped, d)
            .luminance();
        integral += f64::from(le) * 4.0 * std::f64::consts::PI / n as f64;
    }
    let power: f64 = sky.iter().map(|r| f64::from(r.power)).sum();
    assert!(
        (power / integral - 1.0).abs() < 0.02,
        "{power} vs {integral}"
    );
    // Brighter parts get smaller regions: the region of the most power per solid angle is
    // smaller than the mean.
    let densest = sky
        .iter()
        .max_by(|a, b| (a.power / a.solid_angle()).total_cmp(&(b.power / b.solid_angle())))
        .expect("regions");
    assert!(
        densest.solid_angle() < solid / SKY_REGIONS as f32,
        "{densest:?}"
    );
}
