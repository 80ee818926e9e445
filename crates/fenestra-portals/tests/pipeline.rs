//! The estimation pipeline on the box scenes of seed 000 §5.2 (known holes).

use fenestra_portals::estimate::{estimate, EstimateParams};
use fenestra_render::integrator::NoProgress;
use fenestra_render::portal::Portal;
use fenestra_render::{LightSelection, RenderScene};
use fenestra_scene::{builtin, Backend, Scene};
use std::sync::atomic::AtomicBool;

fn scene(name: &str) -> RenderScene {
    let desc = builtin::load(name).expect("builtin");
    RenderScene::new(
        Scene::build(desc, Backend::Obvhs).expect("scene"),
        LightSelection::Power,
    )
}

#[test]
fn explore() {
    for (name, target) in [
        ("box-hole", 2048),
        ("box-4holes", 8192),
        ("box-hole-sky", 2048),
        ("hall-windows", 32768),
    ] {
        let s = scene(name);
        let mut p = EstimateParams::default();
        p.photons.target = Some(target);
        let e = estimate(&s, &p, &AtomicBool::new(false), &NoProgress).expect("estimate");
        println!(
            "{name}: {} photons, {} beams, {} rays, {:?}, {} clusters, {:?}",
            e.photons.points.len(),
            e.photons.beams,
            e.photons.rays,
            e.photons.deposit,
            e.clusters.len(),
            e.timings
        );
        for p in &e.portals {
            let kind = match p.portal {
                Portal::Ellipse { .. } => "ellipse",
                Portal::Quad { .. } => "quad",
                _ => "tri",
            };
            println!(
                "  {kind} c {:?} n {:?} area {:.5} photons {} inliers {}",
                p.portal.center(),
                p.portal.normal(),
                p.portal.area(),
                p.photons,
                p.inliers
            );
        }
    }
}
