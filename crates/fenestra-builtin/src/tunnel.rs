//! The unorthodox case of seed 000 Fig. 5.13: a room lit only through a long square tunnel
//! in its side wall; the emitter sits in a closed chamber at the tunnel's far end with a
//! sphere partly blocking it.

use crate::geometry::{camera, cuboid, wall_with_openings, Assembler};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::{Material, RenderDefaults, SceneDesc, Shape, ShapeKind, TriangleMesh};

pub fn tunnel() -> SceneDesc {
    let mut a = Assembler::default();
    let wall = a.material(Material::diffuse(0.7));
    let lamp = a.material(Material::diffuse(0.0));
    // Room: x, y in [-2, 2], z in [0, 3]; the tunnel runs along +x from x = 2 to x = 4 with
    // a 0.6 m square section centred at y = 0, z = 1.5; the chamber spans x in [4, 5.5].
    let opening = ([-0.3, 1.2], [0.3, 1.8]);
    let mut room = TriangleMesh::quad(Vec3::new(0.0, 0.0, 0.0), Vec3::X * 2.0, Vec3::Y * 2.0); // floor
    room.append(&TriangleMesh::quad(
        Vec3::new(0.0, 0.0, 3.0),
        Vec3::Y * 2.0,
        Vec3::X * 2.0,
    )); // ceiling
    room.append(&TriangleMesh::quad(
        Vec3::new(-2.0, 0.0, 1.5),
        Vec3::Y * 2.0,
        Vec3::Z * 1.5,
    ));
    room.append(&TriangleMesh::quad(
        Vec3::new(0.0, -2.0, 1.5),
        Vec3::Z * 1.5,
        Vec3::X * 2.0,
    ));
    room.append(&TriangleMesh::quad(
        Vec3::new(0.0, 2.0, 1.5),
        Vec3::X * 2.0,
        Vec3::Z * 1.5,
    ));
    // The x = 2 wall with the tunnel mouth, in (y, z) coordinates; normal z x y = -x.
    room.append(&wall_with_openings(
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::Z,
        Vec3::Y,
        ([0.0, -2.0], [3.0, 2.0]),
        &[([1.2, -0.3], [1.8, 0.3])],
    ));
    a.mesh(room, wall);
    // Tunnel sides.
    let mut tube = TriangleMesh::default();
    for (c, hu, hv) in [
        (Vec3::new(3.0, 0.0, 1.2), Vec3::X, Vec3::Y * 0.3),
        (Vec3::new(3.0, 0.0, 1.8), Vec3::Y * 0.3, Vec3::X),
        (Vec3::new(3.0, -0.3, 1.5), Vec3::X, Vec3::Z * 0.3),
        (Vec3::new(3.0, 0.3, 1.5), Vec3::Z * 0.3, Vec3::X),
    ] {
        tube.append(&TriangleMesh::quad(c, hu, hv));
    }
    a.mesh(tube, wall);
    // Chamber: a closed box x in [4, 5.5], y in [-1, 1], z in [0.5, 2.5] entered through the
    // tunnel's far end.
    let mut chamber = wall_with_openings(
        Vec3::new(4.0, 0.0, 0.0),
        Vec3::Y,
        Vec3::Z,
        ([-1.0, 0.5], [1.0, 2.5]),
        &[opening],
    );
    let mut shell = cuboid(Vec3::new(4.0, -1.0, 0.5), Vec3::new(5.5, 1.0, 2.5));
    // Drop the cuboid's x = 4 face (its first two triangles face -x: the second quad).
    shell.indices.drain(2..4);
    chamber.append(&shell);
    a.mesh(chamber, wall);
    let light = TriangleMesh::quad(Vec3::new(5.45, 0.0, 1.5), Vec3::Z * 0.8, Vec3::Y * 0.8);
    a.emitter(ShapeKind::Mesh(light), lamp, Rgb::splat(30.0));
    a.shapes.push(Shape::new(
        ShapeKind::Sphere {
            center: Vec3::new(4.9, 0.15, 1.6),
            radius: 0.45,
        },
        wall,
    ));
    a.finish(
        "tunnel",
        camera(Vec3::new(-1.8, -1.7, 2.2), Vec3::new(1.0, 0.5, 1.0), 70.0),
        RenderDefaults {
            width: 512,
            height: 384,
            spp: 64,
            max_depth: 8,
            options: Vec::new(),
        },
    )
}
