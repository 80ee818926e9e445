//! The estimation pipeline on scenes whose openings are known: the box scenes of seed 000
//! §5.2 carry their holes as manual portals, and the hall's lit windows are listed.

use fenestra_builtin as builtin;
use fenestra_core::Vec3;
use fenestra_portals::aim::camera_surroundings;
use fenestra_portals::estimate::{estimate, Estimate, EstimateParams};
use fenestra_portals::Portal;
use fenestra_render::{NoProgress, RenderScene};
use fenestra_scene::{Backend, Scene};
use std::sync::atomic::AtomicBool;

fn run(name: &str) -> (RenderScene, Estimate) {
    run_with(name, &EstimateParams::default())
}

/// `params` without their time limit: the photons then depend on nothing but the parameters,
/// not on the machine's speed or load.
fn untimed(mut params: EstimateParams) -> EstimateParams {
    params.photons.time_limit = None;
    params
}

/// The estimate of built-in `name` by `params`, untimed.
fn run_with(name: &str, params: &EstimateParams) -> (RenderScene, Estimate) {
    let params = untimed(params.clone());
    let desc = builtin::load(name).expect("builtin");
    let scene = RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"));
    let e = estimate(&scene, &params, &AtomicBool::new(false), &NoProgress).expect("estimate");
    (scene, e)
}

#[test]
fn settled_portals_are_those_of_the_full_photon_target() {
    // box-4holes reaches its 8192 photons; settling stops well before with the same portals.
    let full = EstimateParams {
        settle: None,
        ..EstimateParams::default()
    };
    let (_, all) = run_with("box-4holes", &full);
    let (_, early) = run("box-4holes");
    assert!(!all.photons.settled && early.photons.settled);
    assert!(
        early.photons.beams * 2 <= all.photons.beams,
        "settling traced {} of {} beams",
        early.photons.beams,
        all.photons.beams
    );
    assert_eq!(early.portals.len(), all.portals.len());
    for p in &all.portals {
        let (c, a) = (p.portal.center(), p.portal.area());
        assert!(
            early
                .portals
                .iter()
                .any(|q| (q.portal.center() - c).length() < 1e-4
                    && (q.portal.area() - a).abs() < 1e-4 * a),
            "no settled portal matches {:?}",
            p.portal
        );
    }
}

/// Whether `portal` covers the quad `hole` (corners in order): every corner, pulled 0.1 mm
/// towards the centre, is crossed by a ray along the normal.
fn covers(portal: &Portal, hole: &[Vec3; 4]) -> bool {
    let c = (hole[0] + hole[1] + hole[2] + hole[3]) / 4.0;
    let n = (hole[1] - hole[0]).cross(hole[3] - hole[0]).normalize();
    hole.iter().all(|&q| {
        let q = q + (c - q).normalize() * 1e-4;
        portal.intersect(q - n * 0.1, n).is_some()
    })
}

fn area(q: &[Vec3; 4]) -> f32 {
    (q[1] - q[0]).cross(q[3] - q[0]).length()
}

/// Each hole is covered by exactly one portal, and the portals' total area is at most
/// `max_ratio` times the holes'.
fn check_box(name: &str, holes: usize, max_ratio: f32) {
    let (scene, e) = run(name);
    let truth = &scene.scene.portals;
    assert_eq!(truth.len(), holes);
    assert_eq!(
        e.portals.len(),
        holes,
        "{name}: {} portals",
        e.portals.len()
    );
    for hole in truth {
        let n = e.portals.iter().filter(|p| covers(&p.portal, hole)).count();
        assert_eq!(n, 1, "{name}: hole {hole:?} is covered by {n} portals");
    }
    let ratio = e.portals.iter().map(|p| p.portal.area()).sum::<f32>()
        / truth.iter().map(area).sum::<f32>();
    assert!(
        (1.0..=max_ratio).contains(&ratio),
        "{name}: portals are {ratio} times the holes' area"
    );
}

#[test]
fn box_hole_yields_one_portal_covering_the_hole() {
    check_box("box-hole", 1, 1.01);
}

#[test]
fn box_4holes_yields_four_portals_one_per_hole() {
    check_box("box-4holes", 4, 1.01);
}

#[test]
fn hall_windows_yields_portals_on_the_lit_windows_only() {
    let (_, e) = run("hall-windows");
    let lit = builtin::hall::windows(19, 5.0);
    assert_eq!(e.portals.len(), lit.len());
    for p in &e.portals {
        let c = p.portal.center();
        // The lit wall is y = +3 (the unlit windows are on y = -3).
        assert!((c.y - 3.0).abs() < 1e-3, "portal off the lit wall at {c}");
        let window = lit.iter().position(|([x0, z0], [x1, z1])| {
            (*x0..*x1).contains(&c.x) && (*z0..*z1).contains(&c.z)
        });
        assert!(window.is_some(), "portal at {c} is on no lit window");
        // A pane is 0.5 x 1.6 m: the portal spans it within 1%.
        assert!(
            (p.portal.area() / 0.8 - 1.0).abs() < 0.01,
            "area {}",
            p.portal.area()
        );
    }
    // One portal per window.
    let mut xs: Vec<i32> = e
        .portals
        .iter()
        .map(|p| (p.portal.center().x * 10.0) as i32)
        .collect();
    xs.sort();
    xs.dedup_by(|a, b| (*a - *b).abs() < 3);
    assert_eq!(xs.len(), lit.len());
}

/// A window glazed with a refracting 8 mm pane (photons beyond it reach the room by two
/// refractions), with and without a blind behind the glass: one portal in the wall's reveal,
/// covering the window to 5 mm of its edges and at most 1% larger than it.
#[test]
fn a_glazed_window_yields_one_portal_covering_it() {
    let (lo, hi) = builtin::glazed::WINDOW;
    let inset = 0.005;
    let (x0, z0, x1, z1) = (lo[0] + inset, lo[1] + inset, hi[0] - inset, hi[1] - inset);
    let window = [
        Vec3::new(x0, 0.0, z0),
        Vec3::new(x1, 0.0, z0),
        Vec3::new(x1, 0.0, z1),
        Vec3::new(x0, 0.0, z1),
    ];
    let full = (hi[0] - lo[0]) * (hi[1] - lo[1]);
    for name in ["room-glazed-sky", "room-glazed-blind"] {
        let (_, e) = run(name);
        assert_eq!(e.portals.len(), 1, "{name}: {} portals", e.portals.len());
        let p = &e.portals[0].portal;
        assert!(
            covers(p, &window),
            "{name}: {p:?} leaves the window uncovered"
        );
        assert!(p.area() <= 1.01 * full, "{name}: area {}", p.area());
        // The wall is y in [-0.2, 0].
        let y = p.center().y;
        assert!((-0.2..=0.0).contains(&y), "{name}: portal at y = {y}");
    }
}

/// Light that reaches the room only after a bounce in the next one, through a door ajar:
/// no portal (none on the far room's ceiling panel either, where photons ring the lamp),
/// from the whole photon target.
#[test]
fn a_door_ajar_yields_no_portal() {
    let (_, e) = run("rooms-door-ajar");
    assert!(!e.photons.timed_out);
    let found: Vec<_> = e.portals.iter().map(|p| p.portal.center()).collect();
    assert!(found.is_empty(), "portals at {found:?}");
}

#[test]
fn photons_do_not_depend_on_the_thread_count() {
    use fenestra_portals::photon::{trace, PhotonParams};
    let desc = builtin::load("box-4holes").expect("builtin");
    let scene = RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"));
    // Without a time limit, which would make the photons depend on the machine's speed.
    let params = PhotonParams {
        target: Some(3000),
        time_limit: None,
        ..PhotonParams::default()
    };
    let with = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| {
            trace(
                &scene,
                &params,
                camera_surroundings(&scene.scene).sphere,
                &AtomicBool::new(false),
                &NoProgress,
                &mut |_| false,
            )
        })
        .expect("photons")
    };
    let (one, three) = (with(1), with(3));
    assert_eq!(one.points.len(), 3000);
    assert_eq!(one.points, three.points);
    assert_eq!((one.beams, one.rays), (three.beams, three.rays));
}

/// The estimate of box-hole-sky with extra shapes (material 0, the box's).
fn sky_box_with(shapes: Vec<fenestra_scene::TriangleMesh>) -> ([Vec3; 4], Estimate) {
    use fenestra_scene::{Shape, ShapeKind};
    let mut desc = builtin::load("box-hole-sky").expect("builtin");
    let hole = desc.portals[0];
    for mesh in shapes {
        desc.shapes.push(Shape::new(ShapeKind::Mesh(mesh), 0));
    }
    let scene = RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"));
    let e = estimate(
        &scene,
        &untimed(EstimateParams::default()),
        &AtomicBool::new(false),
        &NoProgress,
    )
    .expect("estimate");
    (hole, e)
}

/// A free-standing object in the light (a square frame of 2 cm bars hanging under
/// box-hole-sky's hole, as a lamp shade in a sunbeam) casts edges into the light and lets it
/// through, but it is no opening: only the hole gets a portal.
#[test]
fn a_free_standing_object_in_the_light_is_no_portal() {
    use fenestra_scene::TriangleMesh;
    let (z, h, w) = (0.4, 0.09, 0.01);
    let bars = [
        (Vec3::new(0.0, h, z), Vec3::X * h, Vec3::Y * w),
        (Vec3::new(0.0, -h, z), Vec3::X * h, Vec3::Y * w),
        (Vec3::new(h, 0.0, z), Vec3::X * w, Vec3::Y * h),
        (Vec3::new(-h, 0.0, z), Vec3::X * w, Vec3::Y * h),
    ]
    .map(|(c, hu, hv)| TriangleMesh::quad(c, hu, hv));
    let (hole, e) = sky_box_with(bars.to_vec());
    assert_eq!(e.portals.len(), 1, "{}", e.summary());
    assert!(covers(&e.portals[0].portal, &hole), "{}", e.summary());
}

/// A window broken up by frames is found as a whole: box-hole-sky's hole with a cross of 2 cm
/// mullions in it (the photons ring the hole and line the mullions) gets one portal covering
/// the hole to its corners, at most 2% larger than it.
#[test]
fn an_opening_with_mullions_is_one_portal() {
    use fenestra_scene::TriangleMesh;
    let bars = [
        (Vec3::X * 0.125, Vec3::Y * 0.01),
        (Vec3::X * 0.01, Vec3::Y * 0.125),
    ]
    .map(|(hu, hv)| TriangleMesh::quad(Vec3::new(0.0, 0.0, 0.5), hu, hv));
    let (hole, e) = sky_box_with(bars.to_vec());
    assert_eq!(e.portals.len(), 1, "{}", e.summary());
    let portal = &e.portals[0].portal;
    assert!(covers(portal, &hole), "{}", e.summary());
    let ratio = portal.area() / area(&hole);
    assert!(ratio <= 1.02, "the portal is {ratio} times the hole");
}

/// What estimation keeps a portal by: box-hole-sky's hole is open and enclosed by the ceiling;
/// the same square on the ceiling beside it is closed; hanging in the box's middle, it is open
/// and surrounded by open air.
#[test]
fn openings_are_open_and_enclosed_free_squares_are_not() {
    use fenestra_portals::snap::{Opening, MIN_ENCLOSED};
    let desc = builtin::load("box-hole-sky").expect("builtin");
    let hole = desc.portals[0];
    let scene = Scene::build(desc, Backend::Obvhs).expect("scene");
    let glass = vec![false; scene.shapes.len()];
    let opening = Opening::new(&scene, &glass);
    let square = |offset: Vec3| Portal::Quad {
        corner: hole[0] + offset,
        e1: hole[1] - hole[0],
        e2: hole[3] - hole[0],
    };
    let at_hole = square(Vec3::ZERO);
    let beside = square(Vec3::new(0.3, 0.0, 0.0));
    let hanging = square(Vec3::new(0.0, 0.0, -0.5));
    assert!(opening.open_fraction(&at_hole) > 0.99);
    assert!(opening.enclosed_fraction(&at_hole) > 0.99);
    assert!(opening.open_fraction(&beside) < 0.01);
    assert!(opening.open_fraction(&hanging) > 0.99);
    assert!(opening.enclosed_fraction(&hanging) < MIN_ENCLOSED);
}

#[test]
fn the_pilot_keeps_a_portal_over_the_hole_and_refuses_one_on_a_wall() {
    // box-hole's light comes through its ceiling hole alone: a portal over it samples the sky
    // far better than light sampling, and one of the same size on a side wall (wall beyond,
    // nothing comes through) only spends rays. The pilot measures the direct light and one
    // bounce's at the points the camera sees.
    use fenestra_portals::pilot::measure;
    use fenestra_render::light::PowerLightSampler;
    let desc = builtin::load("box-hole").expect("builtin");
    let hole = desc.portals.clone();
    let scene = RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"));
    let lights = PowerLightSampler::new(&scene.scene, &scene.lights);
    let surroundings = camera_surroundings(&scene.scene);
    let gain = |quads: &[[Vec3; 4]]| {
        let portals = fenestra_portals::Portals::from_quads(quads);
        measure(&scene, &portals, (&lights, &lights), &surroundings, None).gain()
    };
    let over_hole = gain(&hole);
    // The hole's quad turned onto the wall at x = +0.5 (the box is the unit cube about the
    // origin), facing into the box.
    let (lo, hi) = (-0.125, 0.125);
    let wall = [[
        Vec3::new(0.5, lo, lo),
        Vec3::new(0.5, hi, lo),
        Vec3::new(0.5, hi, hi),
        Vec3::new(0.5, lo, hi),
    ]];
    let on_wall = gain(&wall);
    assert!(over_hole > 2.0, "over the hole: {over_hole:.2}x");
    assert!(on_wall < 1.0, "on a wall: {on_wall:.2}x");
}

#[test]
fn the_pilot_counts_the_rays_each_estimator_spends() {
    // The sky-lit box with a sun and a lamp inside: beside the portals the compact lights'
    // sampler takes the sun at every vertex and its inner (uniform) pick stands for the rest,
    // a pick of the sky or the sun dropped, so it spends 1 + 1/3 shadow rays; a vertex
    // taking it or a portal's probe ray with probability 1/2 each spends, with its BSDF ray,
    // 1 + (1 + 1/3) / 2 + 1 / 2 rays. Light sampling alone picks one light by power: two rays.
    use fenestra_portals::pilot::measure;
    use fenestra_render::light::{PowerLightSampler, SplitSuns, UniformLightSampler};
    use fenestra_scene::LightDesc;
    let mut desc = builtin::load("box-hole-sky").expect("builtin");
    desc.lights.push(LightDesc::Distant {
        direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
        irradiance: fenestra_core::Rgb::splat(3.0),
    });
    desc.lights.push(LightDesc::Point {
        position: Vec3::new(0.2, 0.2, -0.2),
        intensity: fenestra_core::Rgb::splat(0.1),
    });
    let portals = fenestra_portals::Portals::from_quads(&desc.portals);
    let scene = RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"));
    assert_eq!(scene.lights.lights.len(), 3);
    let lights = PowerLightSampler::new(&scene.scene, &scene.lights);
    let suns = SplitSuns::new(
        Box::new(UniformLightSampler::new(&scene.lights)),
        &scene.lights,
    );
    let surroundings = camera_surroundings(&scene.scene);
    let verdict = measure(&scene, &portals, (&lights, &suns), &surroundings, Some(0.5));
    let expected = 1.0 + (1.0 + 1.0 / 3.0) / 2.0 + 0.5;
    assert!(
        (verdict.portal_rays - expected).abs() < 0.03,
        "{:.4} rays per vertex with the portals, expected {expected:.4}",
        verdict.portal_rays
    );
    assert_eq!(verdict.light_rays, 2.0);
}
