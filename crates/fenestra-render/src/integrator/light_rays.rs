//! The rays of next-event samples, traced by the path loop rather than by the strategy that
//! made them, so that a wave of paths traces them together, eight to a packet query; a
//! single path traces its own at once, the same way. A shadow ray asks whether the way to
//! a sampled light point is clear; a probe ray asks what it meets first (beyond thin
//! glass, and, where its strategy follows them, through the refractions of smooth glass),
//! and the strategy finishes its sample from that.

use super::next_event::sides_agree;
use super::path_options::Sides;
use crate::bsdf::Bsdf;
use crate::light::{LightRecord, LightRecords};
use crate::render_scene::RenderScene;
use fenestra_core::{Frame, Ray, Rgb, Vec3};
use fenestra_scene::{SurfaceInteraction, PACKET};

/// Smooth-glass interfaces a probe passes at most (a double-glazed window has four).
pub const MAX_REFRACTIONS: u32 = 16;

/// A light sample whose way to the light is still to be tested.
#[derive(Clone, Copy, Debug)]
pub struct ShadowRay {
    /// From the shading point towards the light.
    pub ray: Ray,
    /// Where the light is along it (infinity for lights at infinity).
    pub tmax: f32,
    /// What the sample brings where nothing blocks it (through thin glass, times the panes'
    /// transmittance). The path loop multiplies in the path's throughput.
    pub value: Rgb,
    /// The light sampled (its index in the scene's lights).
    pub light: usize,
    /// Its MIS weight against BSDF sampling (1 for a Dirac light), already in `value`.
    pub mis: f32,
    /// The record a learning light sampler keeps of the sample if light arrives, its
    /// weight not yet multiplied by the transmittance.
    pub record: Option<LightRecord>,
}

/// A next-event sample whose light is whatever its ray meets first beyond thin glass: the
/// ray, and what the strategy keeps of the sample (`P`) to finish it once that is known
/// ([`NextEvent::probed`](super::NextEvent::probed)).
#[derive(Clone, Copy, Debug)]
pub struct ProbeRay<P> {
    /// From the shading point.
    pub ray: Ray,
    /// The path's throughput at the shading point (set by the path loop).
    pub beta: Rgb,
    /// How many smooth-glass interfaces the ray goes on through by refraction: 0 (it stops
    /// at smooth glass, as a shadow ray), or as many as the strategy allows, which the path
    /// loop cuts to what the path's length leaves (a refraction is a path vertex).
    pub refractions: u32,
    /// What the strategy keeps of the sample.
    pub probe: P,
}

/// What a probe ray found: the transmittance of the glass it passed, the first other
/// surface (`None`: it left the scene) and the direction it arrived there along. In a scene
/// where no surface emits, a probe that meets a surface reports black transmittance and no
/// surface instead: what it met could send it nothing.
#[derive(Clone, Copy, Debug)]
pub struct Beyond {
    /// Transmittance of the panes and refractions on the way.
    pub tr: Rgb,
    /// The surface met.
    pub surface: Option<SurfaceInteraction>,
    /// The direction of the ray's last segment: its own unless it was refracted.
    pub d: Vec3,
    /// Whether it was refracted on the way (then only strategies whose samples follow
    /// refractions could have found this light).
    pub refracted: bool,
}

/// What `ray` meets beyond thin glass and, through at most `refractions` smooth-glass
/// interfaces, by refraction: each passage keeps (1 - R) / eta'^2 of the radiance, as a
/// camera path that chose refraction there does, and total internal reflection or a path
/// leaving by a surface's shading normal against its geometric one (`sides`) stops it (that
/// light is left to the paths that reflect). The path loop follows the same passages without
/// a new vertex for MIS, so both techniques weigh the same paths.
pub fn beyond_glass(scene: &RenderScene, mut ray: Ray, refractions: u32, sides: Sides) -> Beyond {
    let mut tr = Rgb::ONE;
    let mut refracted = 0;
    loop {
        let (t, surface) = scene.through_glass(ray, f32::INFINITY);
        tr *= t;
        let found = |tr, surface| Beyond {
            tr,
            surface,
            d: ray.d,
            refracted: refracted > 0,
        };
        let Some(si) = surface.filter(|_| refracted < refractions) else {
            return found(tr, surface);
        };
        let bsdf = scene.bsdf_at(&si);
        let Bsdf::SmoothDielectric(glass) = bsdf.as_ref() else {
            return found(tr, Some(si));
        };
        if scene.lights.surface_emission(&si, ray.d).is_some() {
            return found(tr, Some(si));
        }
        let frame = Frame::from_normal(si.ns);
        let wo = -ray.d;
        let wo_local = frame.to_local(wo);
        let Some((wi_local, share)) = glass.transmit(wo_local) else {
            return found(Rgb::ZERO, None);
        };
        let wi = frame.to_world(wi_local);
        if !sides_agree(sides, si.ng, wo, wo_local.z, wi, wi_local.z) {
            return found(Rgb::ZERO, None);
        }
        tr *= share;
        refracted += 1;
        ray = Ray::new(si.spawn(wi), wi);
    }
}

/// The rays that the next-event samples of one vertex, or of a wave's vertices, leave to
/// the path loop.
#[derive(Clone, Debug)]
pub struct LightRays<P> {
    /// Shadow rays, in the order they were made.
    pub shadows: Vec<ShadowRay>,
    /// Probe rays, in the order they were made.
    pub probes: Vec<ProbeRay<P>>,
}

impl<P> Default for LightRays<P> {
    fn default() -> Self {
        LightRays {
            shadows: Vec::new(),
            probes: Vec::new(),
        }
    }
}

impl ShadowRay {
    /// What the sample brings through the transmittance `tr` of its ray (grey: thin glass
    /// lets every channel through alike); its record goes to `records` if light arrives.
    fn arrive(&self, tr: Rgb, records: &mut LightRecords) -> Rgb {
        if tr.is_black() {
            return Rgb::ZERO;
        }
        if let Some(mut record) = self.record {
            record.weight *= tr.max_component();
            records.push(record);
        }
        self.value * tr
    }

    /// Tests the ray: what its sample brings (see [`trace_shadows`]).
    pub fn trace(&self, scene: &RenderScene, records: &mut LightRecords) -> Rgb {
        self.arrive(scene.transmittance(self.ray, self.tmax), records)
    }
}

impl<P> ProbeRay<P> {
    /// Traces the ray: what it meets (see [`trace_probes`]).
    pub fn trace(&self, scene: &RenderScene, sides: Sides) -> Beyond {
        beyond_glass(scene, self.ray, self.refractions, sides)
    }
}

/// Tests the shadow rays `shadows` and calls `arrived(i, value)` with what each brings, in
/// order. Without thin glass, visibility is an any-hit query of eight rays at a time (a
/// short last packet repeats its last ray): which rays share a packet does not change any
/// ray's answer, so the image does not depend on how paths were grouped.
pub fn trace_shadows(
    scene: &RenderScene,
    shadows: &[ShadowRay],
    records: &mut LightRecords,
    mut arrived: impl FnMut(usize, Rgb),
) {
    if scene.has_thin_glass() {
        for (i, shadow) in shadows.iter().enumerate() {
            arrived(i, shadow.trace(scene, records));
        }
        return;
    }
    for (c, chunk) in shadows.chunks(PACKET).enumerate() {
        let last = chunk.len() - 1;
        let rays = std::array::from_fn(|k| chunk[k.min(last)].ray);
        let tmax = std::array::from_fn(|k| chunk[k.min(last)].tmax);
        let blocked = scene.scene.occluded8(&rays, tmax);
        for (k, shadow) in chunk.iter().enumerate() {
            let tr = if blocked[k] { Rgb::ZERO } else { Rgb::ONE };
            arrived(c * PACKET + k, shadow.arrive(tr, records));
        }
    }
}

/// Traces the probe rays `probes` and calls `met(i, beyond)` with what each meets, in order.
/// Without thin glass, and without smooth glass where the probes follow refractions, eight
/// rays at a time by a packet query (see [`trace_shadows`]): an any-hit one where no surface
/// emits (see [`Beyond`]).
pub fn trace_probes<P>(
    scene: &RenderScene,
    probes: &[ProbeRay<P>],
    sides: Sides,
    mut met: impl FnMut(usize, Beyond),
) {
    let refracting = scene.has_smooth_glass() && probes.iter().any(|p| p.refractions > 0);
    if scene.has_thin_glass() || refracting {
        for (i, probe) in probes.iter().enumerate() {
            met(i, probe.trace(scene, sides));
        }
        return;
    }
    for (c, chunk) in probes.chunks(PACKET).enumerate() {
        let last = chunk.len() - 1;
        let rays = std::array::from_fn(|k| chunk[k.min(last)].ray);
        if !scene.has_surface_lights() {
            let blocked = scene.scene.occluded8(&rays, [f32::INFINITY; PACKET]);
            for (k, &blocked) in blocked.iter().take(chunk.len()).enumerate() {
                let tr = if blocked { Rgb::ZERO } else { Rgb::ONE };
                let (d, refracted) = (chunk[k].ray.d, false);
                met(
                    c * PACKET + k,
                    Beyond {
                        tr,
                        surface: None,
                        d,
                        refracted,
                    },
                );
            }
            continue;
        }
        let hits = scene.scene.intersect8(&rays, [f32::INFINITY; PACKET]);
        for (k, probe) in chunk.iter().enumerate() {
            let surface = hits[k].map(|hit| scene.scene.interaction(&probe.ray, &hit));
            met(
                c * PACKET + k,
                Beyond {
                    tr: Rgb::ONE,
                    surface,
                    d: probe.ray.d,
                    refracted: false,
                },
            );
        }
    }
}
