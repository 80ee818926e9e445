//! Interiors lit the way real ones are (issue 64), where the box scenes' open holes and thin
//! panes are not: a window glazed with a refracting pane (a smooth-dielectric slab, 8 mm,
//! with a mullion and a transom) in a 20 cm thick wall under a sky; the same window with a
//! blind behind the glass, lit by an area light outside; and a room lit from the next one
//! through a door ajar (light arrives only after a bounce there, the classic case of
//! bidirectional methods).

use crate::geometry::{camera, cuboid, room, sky, transposed, wall_with_openings, Assembler};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::light::LightDesc;
use fenestra_scene::material;
use fenestra_scene::{Material, RenderDefaults, SceneDesc, ShapeKind, TriangleMesh};

/// Room size (m): the window wall is the one at y = 0, outside is -y.
const W: f32 = 4.0;
const D: f32 = 5.0;
const H: f32 = 2.7;
/// Wall thickness.
const WALL: f32 = 0.2;
/// The window, (x, z) corners.
pub const WINDOW: ([f32; 2], [f32; 2]) = ([1.2, 0.9], [2.8, 2.1]);
/// Pane thickness (m) and index of refraction.
const PANE: f32 = 0.008;
const GLASS_ETA: f32 = 1.5;

/// What lights the glazed room.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lit {
    /// The sky through the bare glazed window.
    Sky,
    /// An area light 2 m outside, facing the window, and a blind of tilted slats behind
    /// the glass.
    LampBlind,
}

/// A parallelepiped from corner `o` along edges `a`, `b`, `c` (right-handed), its faces
/// outward.
fn slab(o: Vec3, a: Vec3, b: Vec3, c: Vec3) -> TriangleMesh {
    let centre = o + (a + b + c) * 0.5;
    let (a, b, c) = (a * 0.5, b * 0.5, c * 0.5);
    let mut m = TriangleMesh::default();
    for (face, u, v) in [
        (centre + a, b, c),
        (centre - a, c, b),
        (centre + b, c, a),
        (centre - b, a, c),
        (centre + c, a, b),
        (centre - c, b, a),
    ] {
        m.append(&TriangleMesh::quad(face, u, v));
    }
    m
}

/// The room's shell: floor, ceiling, the three plain walls and the window wall's two faces
/// with the reveal between them (a wall 20 cm thick).
fn shell() -> (TriangleMesh, TriangleMesh) {
    let (lo, hi) = WINDOW;
    let (floor, mut walls) = room(W, D, H, &[WINDOW]);
    // The wall's outer face.
    walls.append(&wall_with_openings(
        Vec3::new(0.0, -WALL, 0.0),
        Vec3::Z,
        Vec3::X,
        ([0.0, 0.0], [H, W]),
        &transposed(&[WINDOW]),
    ));
    // The reveal: the opening's four sides through the wall.
    let (cx, cz) = ((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0);
    let (hx, hz, hy) = ((hi[0] - lo[0]) / 2.0, (hi[1] - lo[1]) / 2.0, WALL / 2.0);
    for (centre, u, v) in [
        (Vec3::new(lo[0], -hy, cz), Vec3::Y * hy, Vec3::Z * hz),
        (Vec3::new(hi[0], -hy, cz), Vec3::Z * hz, Vec3::Y * hy),
        (Vec3::new(cx, -hy, lo[1]), Vec3::X * hx, Vec3::Y * hy),
        (Vec3::new(cx, -hy, hi[1]), Vec3::Y * hy, Vec3::X * hx),
    ] {
        walls.append(&TriangleMesh::quad(centre, u, v));
    }
    (floor, walls)
}

/// What the rooms of this module propose to render with.
fn defaults() -> RenderDefaults {
    RenderDefaults {
        width: 320,
        height: 240,
        spp: 64,
        max_depth: 8,
        options: Vec::new(),
    }
}

/// The glazed room, lit as `lit` says.
pub fn glazed_room(lit: Lit) -> SceneDesc {
    let mut a = Assembler::default();
    let white = a.material(Material::diffuse(0.7));
    let floor_material = a.material(Material::diffuse(0.45));
    let frame = a.material(Material::diffuse(0.3));
    let glass = a.material(Material::Dielectric(material::Dielectric {
        eta: GLASS_ETA,
    }));
    let (floor, walls) = shell();
    a.mesh(floor, floor_material);
    a.mesh(walls, white);
    // The pane in the middle of the reveal, a mullion and a transom in front of it outside.
    let (lo, hi) = WINDOW;
    let y = -WALL / 2.0;
    a.mesh(
        cuboid(
            Vec3::new(lo[0], y - PANE / 2.0, lo[1]),
            Vec3::new(hi[0], y + PANE / 2.0, hi[1]),
        ),
        glass,
    );
    let mut bars = cuboid(
        Vec3::new(1.975, y - 0.06, lo[1]),
        Vec3::new(2.025, y - PANE, hi[1]),
    );
    bars.append(&cuboid(
        Vec3::new(lo[0], y - 0.06, 1.675),
        Vec3::new(hi[0], y - PANE, 1.725),
    ));
    a.mesh(bars, frame);
    // A table in the room, for something to see besides walls.
    a.mesh(
        cuboid(Vec3::new(1.4, 1.6, 0.7), Vec3::new(2.6, 2.6, 0.75)),
        frame,
    );
    let (name, eye, target) = match lit {
        Lit::Sky => {
            // The ground outside, and the sky (its glow low in the south, no sun disk).
            let ground = a.material(Material::diffuse(0.25));
            a.mesh(
                TriangleMesh::quad(Vec3::new(2.0, -20.0, -0.05), Vec3::X * 20.0, Vec3::Y * 19.8),
                ground,
            );
            let glow = Vec3::new(0.3, -1.0, 0.4).normalize();
            a.lights
                .push(LightDesc::Environment(sky(256, 128, glow, 1.0)));
            (
                "room-glazed-sky",
                Vec3::new(3.6, 4.6, 1.6),
                Vec3::new(2.0, 0.0, 1.2),
            )
        }
        Lit::LampBlind => {
            let lamp = a.material(Material::diffuse(0.0));
            let panel = TriangleMesh::quad(Vec3::new(2.0, -2.2, 1.5), Vec3::Z * 0.8, Vec3::X * 1.0);
            a.emitter(ShapeKind::Mesh(panel), lamp, Rgb::splat(25.0));
            let slats = a.material(Material::diffuse(0.8));
            a.mesh(blind(), slats);
            (
                "room-glazed-blind",
                Vec3::new(3.6, 4.6, 1.4),
                Vec3::new(2.0, 0.0, 1.3),
            )
        }
    };
    a.finish(name, camera(eye, target, 60.0), defaults())
}

/// A blind 3 cm inside the window: 15 slats 5 cm deep every 8 cm, tilted 30 degrees down
/// towards the room.
fn blind() -> TriangleMesh {
    let (lo, hi) = WINDOW;
    let mut m = TriangleMesh::default();
    let tilt = 30f32.to_radians();
    let depth = Vec3::new(0.0, tilt.cos(), -tilt.sin()) * 0.025;
    for k in 0..15 {
        let z = lo[1] + 0.04 + 0.08 * k as f32;
        let centre = Vec3::new((lo[0] + hi[0]) / 2.0, 0.03 + depth.y, z);
        m.append(&TriangleMesh::quad(
            centre,
            Vec3::X * ((hi[0] - lo[0]) / 2.0 - 0.01),
            depth,
        ));
    }
    m
}

/// The doorway in the wall between the two rooms, (y, z) corners.
pub const DOORWAY: ([f32; 2], [f32; 2]) = ([1.5, 0.0], [2.4, 2.05]);

/// Two 4 x 4 m rooms side by side (x in [0, 4] and [4, 8]) joined by a doorway whose door
/// stands 8 degrees ajar into the far room, where a ceiling panel is the only light; the
/// camera looks at the door from the near room.
pub fn door_ajar() -> SceneDesc {
    let mut a = Assembler::default();
    let white = a.material(Material::diffuse(0.7));
    let floor_material = a.material(Material::diffuse(0.4));
    let door_material = a.material(Material::diffuse(0.55));
    let lamp = a.material(Material::diffuse(0.0));
    let (l, d, h) = (8.0, 4.0, 2.7);
    let (floor, mut walls) = room(l, d, h, &[]);
    a.mesh(floor, floor_material);
    walls.append(&wall_with_openings(
        Vec3::new(4.0, 0.0, 0.0),
        Vec3::Y,
        Vec3::Z,
        ([0.0, 0.0], [d, h]),
        &[DOORWAY],
    ));
    a.mesh(walls, white);
    // The door, hinged at the doorway's y = 1.5 side, 8 degrees open into the far room.
    let (lo, hi) = DOORWAY;
    let angle = 8f32.to_radians();
    let width = hi[0] - lo[0];
    let along = Vec3::new(angle.sin(), angle.cos(), 0.0) * width;
    let thick = Vec3::new(angle.cos(), -angle.sin(), 0.0) * 0.04;
    a.mesh(
        slab(
            Vec3::new(4.0, lo[0], 0.0),
            along,
            thick,
            Vec3::Z * (hi[1] - 0.01),
        ),
        door_material,
    );
    // A cupboard in the far room, which the lamp lights and the doorway half sees.
    a.mesh(
        cuboid(Vec3::new(5.0, 3.2, 0.0), Vec3::new(6.5, 3.9, 1.2)),
        door_material,
    );
    let panel = TriangleMesh::quad(Vec3::new(6.5, 1.0, h - 0.01), Vec3::Y * 0.5, Vec3::X * 0.5);
    a.emitter(ShapeKind::Mesh(panel), lamp, Rgb::splat(40.0));
    a.finish(
        "rooms-door-ajar",
        camera(Vec3::new(0.5, 0.4, 1.6), Vec3::new(4.0, 2.2, 1.0), 65.0),
        defaults(),
    )
}
