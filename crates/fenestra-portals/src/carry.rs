//! Which portals carry light to what the camera sees (beyond seed 000, which keeps every
//! cluster's portal): from points the camera sees, rays aimed at points of a portal either go
//! on to a light (the sky, an emitter), passing glass as lp_hf's probe rays do, or stop.
//! A portal through which no light arrives (a desk top's photons, the gap between two desks, a
//! glass vase in a room lit by a lamp) only takes samples from the light sampling it is mixed
//! with, and is dropped.

use crate::aim::Surroundings;
use crate::portal::Portal;
use fenestra_core::{Ray, Sampler, Vec3};
use fenestra_render::integrator::{beyond_glass, Sides, MAX_REFRACTIONS};
use fenestra_render::RenderScene;

/// Points of the surroundings each portal is tried from, and rays from each.
const POINTS: usize = 256;
const RAYS_PER_POINT: usize = 4;
/// A portal through which fewer of the rays than this reach a light is dropped, and so is one
/// that carries less than this share of the light all portals carry (its area times the
/// fraction of its rays that reach a light): a gap between desks lets a little sky through
/// to the floor beneath them, but sampling it takes samples from the windows.
const MIN_CARRY: f32 = 0.01;
const MIN_SHARE: f32 = 0.01;
/// Light counts as coming through a portal when its emitter lies farther beyond the portal's
/// plane (on the side away from the point the ray left) than this share of the portal's size,
/// and than `MIN_BEYOND` metres.
const BEYOND: f32 = 0.02;
const MIN_BEYOND: f32 = 1e-3;

/// Decides whether portals carry light.
pub struct Carry<'a> {
    scene: &'a RenderScene,
    surroundings: &'a Surroundings,
    /// Whether a ray that leaves the scene meets a light (an environment other than the sun).
    sky: bool,
}

impl<'a> Carry<'a> {
    /// The test in `scene` from the camera's `surroundings`.
    pub fn new(scene: &'a RenderScene, surroundings: &'a Surroundings) -> Self {
        let lights = &scene.lights;
        let sky = lights
            .environments
            .iter()
            .any(|&i| !lights.lights[i].is_compact());
        Carry {
            scene,
            surroundings,
            sky,
        }
    }

    /// The fraction of rays from the surroundings through points of `portal` that reach a
    /// light.
    fn fraction(&self, portal: &Portal) -> f32 {
        let points = &self.surroundings.points;
        if points.is_empty() {
            return 0.0;
        }
        let step = points.len().div_ceil(POINTS);
        let beyond = (BEYOND * portal.area().sqrt()).max(MIN_BEYOND);
        let normal = portal.normal();
        let mut sampler = Sampler::new(0, 0x4341_5252, 0);
        let (mut tried, mut carried) = (0usize, 0usize);
        for si in points.iter().step_by(step) {
            for _ in 0..RAYS_PER_POINT {
                let y = portal.sample_area(sampler.next_2d());
                let Some(d) = (y - si.p).try_normalize() else {
                    continue;
                };
                tried += 1;
                // The portal's normal pointed away from the point: "beyond" is along it.
                let n = if normal.dot(d) < 0.0 { -normal } else { normal };
                let ray = Ray::new(si.spawn(d), d);
                carried += usize::from(self.reaches_light(ray, y, n, beyond));
            }
        }
        if tried == 0 {
            return 0.0;
        }
        carried as f32 / tried as f32
    }

    /// The portals (with what goes with them) that carry light, in their order.
    pub fn keep<T>(&self, portals: Vec<T>, portal: impl Fn(&T) -> &Portal) -> Vec<T> {
        let carried: Vec<f32> = portals
            .iter()
            .map(|p| {
                let f = self.fraction(portal(p));
                if f >= MIN_CARRY {
                    f * portal(p).area()
                } else {
                    0.0
                }
            })
            .collect();
        let total: f32 = carried.iter().sum();
        portals
            .into_iter()
            .zip(carried)
            .filter(|(_, c)| *c > 0.0 && *c >= MIN_SHARE * total)
            .map(|(p, _)| p)
            .collect()
    }

    /// Whether `ray`, aimed at the portal's point `y`, meets an emitter farther than `beyond`
    /// past the portal's plane along `n` (its normal pointing away from the ray's origin), or
    /// leaves the scene under a sky, through thin glass and refracting glazing: what lp_hf's
    /// probe ray through a portal finds. An emitter at the portal itself, or in front of it,
    /// is no light through an opening: the photons that ring a ceiling panel outline the
    /// panel, whose own sampling is the better.
    fn reaches_light(&self, ray: Ray, y: Vec3, n: Vec3, beyond: f32) -> bool {
        let found = beyond_glass(self.scene, ray, MAX_REFRACTIONS, Sides::Shading);
        match found.surface {
            Some(si) => {
                (si.p - y).dot(n) > beyond
                    && (self.scene.lights.surface_emission(&si, found.d))
                        .is_some_and(|(_, le)| !le.is_black())
            }
            None => self.sky && !found.tr.is_black(),
        }
    }
}
