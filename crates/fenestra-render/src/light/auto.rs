//! The default light selection (beyond the seeds): one light per next-event estimate by
//! power, or each light at infinity sampled at every vertex ([`SplitLightSampler::at_infinity`])
//! where a pilot measures that it pays. On a room lit by a sky and a sun a single pick leaves
//! the sunlit patches' direct light a coin toss between the two: splitting them cut the
//! variance per sample 2-2.6x on the sunlit glTF rooms (docs/interiors.md), but where the
//! sun's noise is its bounce light found by BSDF sampling rather than the toss, the extra
//! light sample per vertex costs more than it gains (Bitterli's classroom). Before rendering,
//! at the points the camera sees, both samplers estimate the light a white diffuse surface
//! there reflects (its direct light and one bounce's, each light sample weighted against a
//! cosine sample by MIS), side by side: their variances summed over the points, times the
//! rays each spends, say which to use.

use super::probe::{DiffuseProbe, Moments, ALBEDO};
use super::{
    LightContext, LightHit, LightSample, LightSampler, Lights, Picks, PowerLightSampler,
    SplitLightSampler,
};
use crate::render_scene::RenderScene;
use crate::sample_context::SampleContext;
use fenestra_core::{Sampler, Vec2, Vec3};
use fenestra_scene::Scene;

/// How many times as efficient as power selection the pilot must measure splitting to choose
/// it. The pilot counts rays, where a light sample also evaluates the BSDF and the light's
/// density (on pbrt-v4's coated materials a random walk: on Bitterli's classroom split's
/// samples cost 1.75x power's where its rays are 1.3x), and it sees the direct light and one
/// bounce, where a path's longer tail shares more of the noise: its gains ran 1.3-2x those
/// measured at equal time (docs/interiors.md: 1.17 where splitting lost, 0.77x; 2.3, 3.1 and
/// 4.8 where it won, 2.6x, 1.6x and 2.0x).
pub const SPLIT_MARGIN: f64 = 1.5;
/// Samples of each estimator at each point.
const SAMPLES: u32 = 8;
/// Points the camera sees used at most.
const POINTS: usize = 2048;

/// Power selection, or the lights at infinity split off where that measures more efficient.
pub struct AutoLightSampler {
    chosen: Box<dyn LightSampler>,
    /// The split sampler's measured efficiency over power selection, when measured.
    gain: Option<f64>,
}

impl AutoLightSampler {
    /// Measures the two samplers on `scene` (unless they are the same: fewer than two lights,
    /// or none at infinity) and keeps split where it measures [`SPLIT_MARGIN`] times as efficient.
    pub fn new(scene: &RenderScene) -> Self {
        let lights = &scene.lights;
        let power = Box::new(PowerLightSampler::new(&scene.scene, lights));
        let split = SplitLightSampler::at_infinity(&scene.scene, lights);
        if split.picks() < 2 {
            return AutoLightSampler {
                chosen: power,
                gain: None,
            };
        }
        let (points, _) = fenestra_scene::view::camera_hits(&scene.scene);
        let gain = measure(scene, &points, power.as_ref(), &split);
        AutoLightSampler {
            chosen: if gain >= SPLIT_MARGIN {
                Box::new(split)
            } else {
                power
            },
            gain: Some(gain),
        }
    }
}

/// How many times as efficient `split` is as `power` at `points`: the variance of a two-vertex
/// estimate of the light reflected at each point (its direct light, and the direct light of
/// the surface a cosine sample finds, reflected at [`ALBEDO`]: a sunlit patch seen from the
/// shade is where most of a sunlit room's noise comes from, and splitting helps it less than
/// the patch itself), summed over the points, times the rays each spends (per vertex the
/// BSDF's and one shadow ray per light picked).
fn measure(
    scene: &RenderScene,
    points: &[fenestra_scene::SurfaceInteraction],
    power: &dyn LightSampler,
    split: &SplitLightSampler,
) -> f64 {
    let camera = scene.scene.camera.position;
    let step = points.len().div_ceil(POINTS).max(1);
    let context = SampleContext::SINGLE;
    let samplers: [&dyn LightSampler; 2] = [power, split];
    let (mut variance, mut rays) = ([0.0; 2], [0.0; 2]);
    for (k, si) in points.iter().enumerate().step_by(step) {
        let x = DiffuseProbe::facing(scene, si, camera, &context);
        let mut sampler = Sampler::new(0, 0x5350_4c54, k as u32);
        let mut moments = [Moments::default(), Moments::default()];
        for _ in 0..SAMPLES {
            let wi = x.cosine_direction(&mut sampler);
            let (found, surface) = x.look(wi, 0);
            let y = (surface.as_ref())
                .map(|(y, tr)| (DiffuseProbe::facing(scene, y, x.si.p, &context), *tr));
            let wy = y.as_ref().map(|(y, _)| y.cosine_direction(&mut sampler));
            let found_y = y.as_ref().zip(wy).map(|((y, _), w)| y.found(w));
            for (s, lights) in samplers.iter().enumerate() {
                let (direct, picked) = x.light_estimate(*lights, false, 1.0, &mut sampler);
                let mut estimate = direct + x.bsdf_estimate(*lights, wi, &found);
                rays[s] += 1.0 + picked as f64;
                if let (Some((y, tr)), Some(w), Some(found_y)) = (&y, wy, &found_y) {
                    let (direct, picked) = y.light_estimate(*lights, false, 1.0, &mut sampler);
                    let at_y = direct + y.bsdf_estimate(*lights, w, found_y);
                    estimate += ALBEDO * tr * at_y;
                    rays[s] += 1.0 + picked as f64;
                }
                moments[s].add(estimate);
            }
        }
        for s in 0..2 {
            variance[s] += moments[s].variance();
        }
    }
    let (power_cost, split_cost) = (variance[0] * rays[0], variance[1] * rays[1]);
    if split_cost > 0.0 {
        power_cost / split_cost
    } else if power_cost > 0.0 {
        f64::INFINITY
    } else {
        1.0
    }
}

impl LightSampler for AutoLightSampler {
    fn sample(&self, ctx: &LightContext, u: f32) -> Option<(usize, f32)> {
        self.chosen.sample(ctx, u)
    }

    fn pmf(&self, ctx: &LightContext, light: usize) -> f32 {
        self.chosen.pmf(ctx, light)
    }

    fn sample_li(
        &self,
        scene: &Scene,
        lights: &Lights,
        ctx: &LightContext,
        pick: (usize, f32),
        u: Vec2,
    ) -> Option<LightSample> {
        self.chosen.sample_li(scene, lights, ctx, pick, u)
    }

    fn pdf_li(
        &self,
        scene: &Scene,
        lights: &Lights,
        ctx: &LightContext,
        light: usize,
        wi: Vec3,
        hit: LightHit,
    ) -> f32 {
        self.chosen.pdf_li(scene, lights, ctx, light, wi, hit)
    }

    fn sample_all(&self, ctx: &LightContext, u: f32, picks: &mut Picks) {
        self.chosen.sample_all(ctx, u, picks)
    }

    fn choice(&self) -> Option<(String, f64)> {
        let gain = self.gain?;
        let what = if gain >= SPLIT_MARGIN {
            format!(
                "light selection: each light at infinity sampled at every vertex, measured \
                 {gain:.2}x as efficient as one light by power at the points the camera sees"
            )
        } else {
            format!(
                "light selection: one light by power; sampling each light at infinity at every \
                 vertex measured {gain:.2}x as efficient at the points the camera sees (it must \
                 measure {SPLIT_MARGIN}x to pay)"
            )
        };
        Some((what, gain))
    }
}
