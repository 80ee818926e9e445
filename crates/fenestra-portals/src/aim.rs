//! Where photons from lights at infinity (an environment, the sun) are aimed: at the camera's
//! surroundings rather than at the whole scene. A scene's bounds can be a hundred times the room
//! the camera stands in (Bitterli's classroom has a ground plane of +-110 m): photons spread over
//! them almost all land outside the room and find none of its windows.

use fenestra_core::Vec3;
use fenestra_scene::{Scene, SurfaceInteraction};

/// Hits farther from the camera than this many times the median hit distance are views out
/// (through a window, past the end of an open scene) and do not bound the surroundings.
const FAR: f32 = 4.0;
/// Of the hits left, this fraction at each end of each axis is left out (stray views out).
const TRIM: f64 = 0.01;
/// The box of the hits grows by this fraction of its size on each side, to take in the walls'
/// outer faces and what stands just outside.
const MARGIN: f32 = 0.1;
/// Fewer hits than this and the camera's surroundings are not known: the whole scene is aimed at.
const MIN_HITS: usize = 64;

/// What the camera sees around it.
pub struct Surroundings {
    /// The surface points the camera's rays met.
    pub points: Vec<SurfaceInteraction>,
    /// The sphere (centre, radius) photons from lights at infinity are aimed at: the box of
    /// `points` (and the camera), views out left aside, grown by a margin and kept within the scene's bounds; the
    /// scene's bounding sphere when the camera sees too little.
    pub sphere: (Vec3, f32),
}

/// The camera's surroundings in `scene`.
pub fn camera_surroundings(scene: &Scene) -> Surroundings {
    let camera = &scene.camera;
    let (mut hits, around) = fenestra_scene::view::camera_hits(scene);
    hits.extend(around);
    let whole = scene.bounding_sphere();
    if hits.len() < MIN_HITS {
        return Surroundings {
            points: hits,
            sphere: whole,
        };
    }
    let distance = |si: &SurfaceInteraction| (si.p - camera.position).length();
    let mut distances: Vec<f32> = hits.iter().map(distance).collect();
    let median = *distances
        .select_nth_unstable_by(hits.len() / 2, f32::total_cmp)
        .1;
    let near: Vec<Vec3> = hits
        .iter()
        .filter(|si| distance(si) <= FAR * median)
        .map(|si| si.p)
        .collect();
    let axis = |i: usize| {
        let mut v: Vec<f32> = near.iter().map(|p| p[i]).collect();
        let (n, k) = (v.len(), (TRIM * v.len() as f64) as usize);
        let lo = *v.select_nth_unstable_by(k, f32::total_cmp).1;
        let hi = *v.select_nth_unstable_by(n - 1 - k, f32::total_cmp).1;
        (lo.min(camera.position[i]), hi.max(camera.position[i]))
    };
    let (x, y, z) = (axis(0), axis(1), axis(2));
    let (lo, hi) = (Vec3::new(x.0, y.0, z.0), Vec3::new(x.1, y.1, z.1));
    let margin = (hi - lo) * MARGIN;
    let (bounds_lo, bounds_hi) = scene.bounds();
    let lo = (lo - margin).max(bounds_lo);
    let hi = (hi + margin).min(bounds_hi);
    let radius = 0.5 * (hi - lo).length();
    let sphere = if radius > 0.0 && radius < whole.1 {
        ((lo + hi) * 0.5, radius)
    } else {
        whole
    };
    Surroundings {
        points: hits,
        sphere,
    }
}
