//! Photon tracing with cone-beams, PT(theta, n, r) (seed 000 §4.2, Alg. 1, Fig. 4.6): points
//! are deposited where a beam of light from an emitter is partly stopped by a surface close
//! to the emitter and partly travels on (a depth discontinuity), which outlines the openings
//! light enters through. The material-aware variant (§5.3) deposits on glass instead, and on
//! what surrounds it within a beam.
//!
//! Our reading of Alg. 1 and Fig. 4.6: a beam whose rays are not all stopped by the scene
//! (a gray ray escapes) deposits nothing; a ray deposits its hit x' when x' lies farther than
//! r from the central hit x and in front of the surface at x, on the light's side (green);
//! hits within r of x (red: no discontinuity) or behind that surface's plane (blue: the far
//! side) deposit nothing. (Alg. 1's plane through x faces the emitter; the surface's own plane
//! keeps a slanted floor or ground from passing for an edge.) The pseudo-code's "remove the
//! beam's points" on the first failing ray would reject every beam that crosses an opening's
//! edge, since its central ray passes the opening; the figure deposits exactly those, so the
//! test is per ray.

use crate::error::PortalError;
use fenestra_core::distribution::Distribution1D;
use fenestra_core::ray::{offset_distance, offset_origin};
use fenestra_core::{warp, Frame, Ray, Sampler, UnknownName, Vec3};
use fenestra_render::{Progress, RenderScene};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Which hits of a beam become photons.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Deposit {
    /// Depth discontinuities only (Alg. 1).
    Depth,
    /// Hits on glass (transmissive materials), §5.3.
    Material,
}

impl std::str::FromStr for Deposit {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, UnknownName> {
        match s {
            "depth" => Ok(Deposit::Depth),
            "material" => Ok(Deposit::Material),
            _ => Err(UnknownName::new("deposit rule", s, "depth or material")),
        }
    }
}

impl std::fmt::Display for Deposit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Deposit::Depth => "depth",
            Deposit::Material => "material",
        })
    }
}

impl fenestra_render::options::OptionValue for Deposit {
    const KIND: fenestra_render::options::Kind =
        fenestra_render::options::Kind::Choice(&["depth", "material"]);

    fn from_param(param: &serde_json::Value) -> Result<Self, fenestra_render::options::ValueError> {
        let bad = |e: String| fenestra_render::options::ValueError(e);
        match param {
            serde_json::Value::String(s) => s.parse().map_err(|e: UnknownName| bad(e.to_string())),
            v => Err(bad(format!("takes depth or material, got {v}"))),
        }
    }
}

/// PT(theta, n, r) and when to stop.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PhotonParams {
    /// Cone half-angle theta in degrees (seed §5.2: 3).
    pub theta_deg: f32,
    /// Rays per beam n (32).
    pub rays_per_beam: u32,
    /// Radius r of the rejection sphere in metres (1.2).
    pub reject_radius: f32,
    /// `None`: material-aware when the scene has glass, depth discontinuities otherwise.
    pub deposit: Option<Deposit>,
    /// Stop once this many photons are gathered (seed §5.2: 2048 for one hole, 8192 for
    /// four). `None`: 8192 by depth; 32768 by material, where every beam that reaches glass
    /// deposits its 32 rays in clumps and large panes need more of them to be dense
    /// everywhere.
    pub target: Option<usize>,
    /// Give up after this many beams even if the target is not reached.
    pub max_beams: u64,
    /// Give up after this many seconds even if the target is not reached (checked between
    /// batches of beams; `None`: no limit, the photons then depend on nothing but the
    /// parameters). Where light does not reach what the camera sees through any opening,
    /// no photon may ever be deposited: without a limit a room lit from the next one traced
    /// the 4,194,304 beams of the beam limit, 21 s.
    #[serde(default)]
    pub time_limit: Option<f64>,
    /// Seed of the beams' sample streams.
    pub seed: u64,
}

impl Default for PhotonParams {
    fn default() -> Self {
        PhotonParams {
            theta_deg: 3.0,
            rays_per_beam: 32,
            reject_radius: 1.2,
            deposit: None,
            target: None,
            max_beams: 1 << 22,
            time_limit: Some(TIME_LIMIT),
            seed: 0,
        }
    }
}

/// The photons of one tracing run.
#[derive(Clone, Debug)]
pub struct Photons {
    /// Where photons were deposited.
    pub points: Vec<Vec3>,
    /// Beams traced (each is one emitted ray and, if it hits, n cone rays).
    pub beams: u64,
    /// Rays traced in all.
    pub rays: u64,
    /// The deposit rule used.
    pub deposit: Deposit,
    /// The number of photons aimed at.
    pub target: usize,
    /// Tracing stopped by the user before the target was reached.
    pub interrupted: bool,
    /// Tracing stopped before the target because the caller found the photons enough.
    pub settled: bool,
    /// Tracing stopped before the target because its time limit was reached.
    pub timed_out: bool,
}

/// Seconds photon tracing takes at most by default: with the fits of the settling test and
/// the last fit, estimation stays under a second.
pub const TIME_LIMIT: f64 = 0.5;

/// Beams traced between checks of the target and of Ctrl-C; the photons of a batch are added
/// in beam order, so the result does not depend on the number of threads.
const BATCH: u64 = 8192;
/// Beams per parallel work item (one scratch buffer each).
const CHUNK: u64 = 256;

/// Traces cone-beams from the scene's lights (those at infinity aimed at the sphere `aim`,
/// centre and radius: see [`crate::aim`]) until the target number of photons is gathered,
/// `params.max_beams` beams are spent, `params.time_limit` has passed, `enough` says so of
/// the photons so far (asked after each batch) or `cancel` is set (then the photons so far
/// are kept).
pub fn trace(
    scene: &RenderScene,
    params: &PhotonParams,
    aim: (Vec3, f32),
    cancel: &AtomicBool,
    progress: &dyn Progress,
    enough: &mut dyn FnMut(&[Vec3]) -> bool,
) -> Result<Photons, PortalError> {
    let lights = &scene.lights.lights;
    let powers: Vec<f32> = lights.iter().map(|l| l.power(&scene.scene)).collect();
    if powers.iter().all(|&p| !(p > 0.0)) {
        return Err(PortalError::NoLight);
    }
    if !(params.theta_deg > 0.0 && params.theta_deg < 90.0) {
        return Err(PortalError::Parameters(format!(
            "cone angle theta must lie in (0, 90) degrees, not {}",
            params.theta_deg
        )));
    }
    if params.max_beams > u32::MAX as u64 {
        // Beam indices address the beams' sample streams as u32.
        return Err(PortalError::Parameters(format!(
            "at most {} beams, not {}",
            u32::MAX,
            params.max_beams
        )));
    }
    if params.time_limit.is_some_and(|t| !(t > 0.0)) {
        return Err(PortalError::Parameters(format!(
            "the time limit must be positive, not {}",
            params.time_limit.unwrap_or_default()
        )));
    }
    if params.rays_per_beam == 0 || !(params.reject_radius >= 0.0) {
        return Err(PortalError::Parameters(
            "a beam needs at least one ray and a non-negative rejection radius".into(),
        ));
    }
    let glass = glass_shapes(scene);
    let deposit = deposit_rule(scene, params);
    let target = params.target.unwrap_or(match deposit {
        Deposit::Depth => 8192,
        Deposit::Material => 32768,
    });
    let tracer = BeamTracer {
        scene,
        params,
        aim,
        parallel_radius: aim.1 * params.theta_deg.to_radians().tan(),
        pick: Distribution1D::new(&powers),
        glass,
        deposit,
        cap: 1.0 - params.theta_deg.to_radians().cos(),
    };
    progress.start(Some(target as u64));
    let started = std::time::Instant::now();
    let mut photons = Photons {
        points: Vec::with_capacity(target),
        target,
        beams: 0,
        rays: 0,
        deposit,
        interrupted: false,
        settled: false,
        timed_out: false,
    };
    while photons.points.len() < target && photons.beams < params.max_beams {
        if cancel.load(Ordering::Relaxed) {
            photons.interrupted = true;
            break;
        }
        let start = photons.beams;
        let end = (start + BATCH).min(params.max_beams);
        let chunks: Vec<(Vec<Vec3>, u64)> = (start..end)
            .step_by(CHUNK as usize)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|c| {
                let mut points = Vec::new();
                let mut rays = 0;
                for beam in c..(c + CHUNK).min(end) {
                    rays += tracer.beam(beam, &mut points);
                }
                (points, rays)
            })
            .collect();
        let before = photons.points.len();
        for (points, rays) in chunks {
            photons.points.extend(points);
            photons.rays += rays;
        }
        photons.beams = end;
        photons.points.truncate(target);
        progress.advance((photons.points.len() - before) as u64);
        if photons.points.len() < target && enough(&photons.points) {
            photons.settled = true;
            break;
        }
        let late = params
            .time_limit
            .is_some_and(|t| started.elapsed().as_secs_f64() >= t);
        if photons.points.len() < target && photons.beams < params.max_beams && late {
            photons.timed_out = true;
            break;
        }
    }
    Ok(photons)
}

/// Which shapes are glass (transmissive materials).
pub(crate) fn glass_shapes(scene: &RenderScene) -> Vec<bool> {
    scene
        .scene
        .shapes
        .iter()
        .map(|s| scene.bsdfs[s.material].is_transmissive())
        .collect()
}

/// The deposit rule `trace` uses: the parameters', else material when the scene has glass,
/// depth discontinuities otherwise.
pub fn deposit_rule(scene: &RenderScene, params: &PhotonParams) -> Deposit {
    params
        .deposit
        .unwrap_or(if glass_shapes(scene).iter().any(|&g| g) {
            Deposit::Material
        } else {
            Deposit::Depth
        })
}

struct BeamTracer<'a> {
    scene: &'a RenderScene,
    params: &'a PhotonParams,
    /// The sphere (centre, radius) beams from lights at infinity are aimed at.
    aim: (Vec3, f32),
    /// The radius of their parallel beams: the footprint of a cone of angle theta whose apex
    /// lies on the far side of that sphere.
    parallel_radius: f32,
    pick: Distribution1D,
    glass: Vec<bool>,
    deposit: Deposit,
    /// The beam cone's cap height on the unit sphere, 1 - cos(theta).
    cap: f32,
}

/// Follow-up beams traced around a beam that deposited photons (seed §4.2: "once an area
/// with depth discontinuity has been detected, it should be sampled as much as possible").
const FOLLOW_UPS: u32 = 8;
/// Their central directions lie within this many cone angles of the successful beam's.
const FOLLOW_UP_SPREAD: f32 = 2.0;

impl BeamTracer<'_> {
    /// One iteration of Alg. 1 and, if it deposited photons, its follow-up beams: appends the
    /// photons to `out`, returns the rays traced. Light from infinity arrives as parallel rays
    /// (a cone from an origin outside the scene would spread over many metres): its beams are
    /// cylinders of rays around the central one.
    fn beam(&self, index: u64, out: &mut Vec<Vec3>) -> u64 {
        let scene = &self.scene.scene;
        let mut sampler = Sampler::new(self.params.seed, 0x5048_4f54, index as u32);
        let (light, _, _) = self.pick.sample_discrete(sampler.next_1d());
        let (u_pos, u_dir) = (sampler.next_2d(), sampler.next_2d());
        let light = &self.scene.lights.lights[light];
        let Some(emitted) = light.sample_ray_aimed(scene, self.aim, u_pos, u_dir) else {
            return 0;
        };
        let parallel = light.at_infinity();
        // Off the emitter by the rounding of a point of its magnitude.
        let off = offset_distance(emitted.origin.abs().max_element());
        let y = offset_origin(emitted.origin, emitted.dir, emitted.dir, off);
        let before = out.len();
        let mut rays = self.beam_from(y, emitted.dir, parallel, &mut sampler, out);
        if out.len() > before {
            let frame = Frame::from_normal(emitted.dir);
            let spread = 1.0
                - (FOLLOW_UP_SPREAD * self.params.theta_deg)
                    .to_radians()
                    .cos();
            for _ in 0..FOLLOW_UPS {
                let u = sampler.next_2d();
                rays += if parallel {
                    let d = warp::square_to_disk_concentric(u)
                        * (FOLLOW_UP_SPREAD * self.parallel_radius);
                    let origin = y + frame.to_world(Vec3::new(d.x, d.y, 0.0));
                    self.beam_from(origin, emitted.dir, true, &mut sampler, out)
                } else {
                    let d = frame.to_world(warp::square_to_uniform_cone(u, spread));
                    self.beam_from(y, d, false, &mut sampler, out)
                };
            }
        }
        rays
    }

    /// A ray from `y` along `dir` and, where it hits at x, the beam of n rays around it (a
    /// cone from `y`, or with `parallel` rays along `dir` from the disk around `y`) with the
    /// deposit rule; returns the rays traced.
    fn beam_from(
        &self,
        y: Vec3,
        dir: Vec3,
        parallel: bool,
        sampler: &mut Sampler,
        out: &mut Vec<Vec3>,
    ) -> u64 {
        let scene = &self.scene.scene;
        let central = Ray::new(y, dir);
        let Some(hit) = scene.intersect(&central, f32::INFINITY) else {
            return 1;
        };
        let x = y + dir * hit.t;
        // A hit nearer the emitter than x and farther than r from x needs |x - y| > r: beams
        // that cannot deposit by depth are not traced.
        if self.deposit == Deposit::Depth && hit.t <= self.params.reject_radius {
            return 1;
        }
        // The surface's plane at x, facing the emitter (what the depth rule tests against).
        let facing = match self.deposit {
            Deposit::Depth => {
                let ng = scene.interaction(&central, &hit).ng;
                if ng.dot(dir) > 0.0 {
                    -ng
                } else {
                    ng
                }
            }
            Deposit::Material => Vec3::ZERO,
        };
        let frame = Frame::from_normal(dir);
        let first = out.len();
        let n = self.params.rays_per_beam;
        for i in 0..n {
            let u = sampler.next_2d();
            let ray = if parallel {
                let d = warp::square_to_disk_concentric(u) * self.parallel_radius;
                Ray::new(y + frame.to_world(Vec3::new(d.x, d.y, 0.0)), dir)
            } else {
                Ray::new(y, frame.to_world(warp::square_to_uniform_cone(u, self.cap)))
            };
            let Some(h) = scene.intersect(&ray, f32::INFINITY) else {
                // A gray ray: light escapes, the beam says nothing about an opening.
                out.truncate(first);
                return 2 + i as u64;
            };
            let xp = ray.o + ray.d * h.t;
            let keep = match self.deposit {
                Deposit::Depth => self.discontinuity(x, facing, xp),
                Deposit::Material => self.glass[h.shape as usize],
            };
            if keep {
                out.push(xp);
            }
        }
        1 + n as u64
    }

    /// Whether a beam ray's hit `xp` lies across a depth discontinuity from the central hit
    /// `x`: farther than r from it, and in front of the surface there (`facing`, its normal on
    /// the emitter's side) by more than a tenth of r. Alg. 1 tests the side of the plane
    /// through x facing the emitter; across a slanted floor or ground, half a beam's hits lie
    /// on its near side with no edge between them, and the ground of an open scene filled
    /// the classroom's photons with such noise.
    fn discontinuity(&self, x: Vec3, facing: Vec3, xp: Vec3) -> bool {
        let r = self.params.reject_radius;
        (xp - x).length() > r && (xp - x).dot(facing) > 0.1 * r
    }
}
