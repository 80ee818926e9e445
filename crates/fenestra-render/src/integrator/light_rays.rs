//! The rays of next-event samples, traced by the path loop rather than by the strategy that
//! made them, so that a wave of paths traces them together, eight to a packet query; a
//! single path traces its own at once, the same way. A shadow ray asks whether the way to
//! a sampled light point is clear; a probe ray asks what it meets first (beyond thin
//! glass), and the strategy finishes its sample from that.

use crate::light::{LightRecord, LightRecords};
use crate::render_scene::RenderScene;
use fenestra_core::{Ray, Rgb};
use fenestra_scene::{SurfaceInteraction, PACKET};

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
    /// What the strategy keeps of the sample.
    pub probe: P,
}

/// What a probe ray found: the transmittance of the thin glass it passed, and the first
/// other surface (`None`: it left the scene). In a scene where no surface emits, a probe
/// that meets a surface reports black transmittance and no surface instead: what it met
/// could send it nothing.
#[derive(Clone, Copy, Debug)]
pub struct Beyond {
    /// Transmittance of the panes on the way.
    pub tr: Rgb,
    /// The surface met.
    pub surface: Option<SurfaceInteraction>,
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
    pub fn trace(&self, scene: &RenderScene) -> Beyond {
        let (tr, surface) = scene.through_glass(self.ray, f32::INFINITY);
        Beyond { tr, surface }
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
/// Without thin glass, eight rays at a time by a packet query (see [`trace_shadows`]): an
/// any-hit one where no surface emits (see [`Beyond`]).
pub fn trace_probes<P>(
    scene: &RenderScene,
    probes: &[ProbeRay<P>],
    mut met: impl FnMut(usize, Beyond),
) {
    if scene.has_thin_glass() {
        for (i, probe) in probes.iter().enumerate() {
            met(i, probe.trace(scene));
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
                met(c * PACKET + k, Beyond { tr, surface: None });
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
                },
            );
        }
    }
}
