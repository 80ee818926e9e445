//! `lp_lt`: lp_hf's camera paths and light paths from the suns through the same portals,
//! joined by MIS (issue 66). A path lit straight by a sun is made by lp_hf's next-event
//! sample of the sun at its last vertex and by a light path connected to the camera at its
//! first (light tracing, t = 1); each is weighted by the power heuristic (or the path options'
//! MIS) over the two densities of the whole path ([`fenestra_render::integrator::CameraSide`],
//! Veach 1997 §10.2), so the sun's glints thrown by glossy surfaces onto what the camera sees
//! go to the light paths and its direct light stays with next-event estimation, by weight.
//! Everything else (the sky through the portals, other lights, paths through mirrors and
//! glass seen by the camera) is lp_hf's alone. Whether light paths pay is measured before
//! rendering by a trial ([`crate::trial`]), and where on the portals they start can be
//! learned by a pilot ([`crate::emission`]).

use crate::light_passes::LightPasses;
use crate::light_paths::{suns_through, SunPaths};
use crate::lp_hf::PortalNextEvent;
use crate::trial::{self, Trial};
use fenestra_core::stats::RenderStats;
use fenestra_render::film::Film;
use fenestra_render::integrator::{PathTracer, Split};
use fenestra_render::options::{OptionError, Options, Validate};
use fenestra_render::settings::RenderSettings;
use fenestra_render::{Integrator, IntegratorError, RenderControl, RenderScene};
use std::sync::Arc;
use std::time::Instant;

fenestra_render::options! {
    /// Light paths from the suns through the portals, joined to the camera paths.
    #[derive(Copy)]
    pub struct LightPathOptions in "light_paths", flags "light-paths" {
        /// Light paths traced per camera sample (0 to 16; fractions spread them over the
        /// pixel's samples; 0.25 was the most efficient of 0.25-2 on the classroom, the
        /// dining room and the glossy room, docs/interiors.md).
        pub per_sample: f32 = 0.25,
        /// Light paths of a pilot before rendering that learns where on the portals light
        /// paths should start (0: uniformly over them; 32768 learned in 0.04-0.08 s, and the
        /// learned emission measured 0.85-0.99x uniform's efficiency on the sunlit rooms of
        /// docs/interiors.md, whose glossy surfaces fill the sunlit patches).
        pub pilot: u32 = 0,
        /// Camera samples of a trial before rendering (a small image rendered with light
        /// paths and without), whose variance times rays decides whether light paths are
        /// traced (0: always; 32768 took 0.05-0.38 s on the sunlit rooms of
        /// docs/interiors.md, and decided as rendering measured on all seven).
        pub trial: u32 = 32768,
    }
}

impl Validate for LightPathOptions {
    fn validate(&self) -> Result<(), OptionError> {
        if !(0.0..=16.0).contains(&self.per_sample) {
            return Err(OptionError::new(
                "per_sample",
                format!("must lie in [0, 16], got {}", self.per_sample),
            ));
        }
        if self.pilot > MAX_PILOT {
            return Err(OptionError::new(
                "pilot",
                format!("must lie in [0, {MAX_PILOT}], got {}", self.pilot),
            ));
        }
        if self.trial > MAX_PILOT {
            return Err(OptionError::new(
                "trial",
                format!("must lie in [0, {MAX_PILOT}], got {}", self.trial),
            ));
        }
        Ok(())
    }
}

/// The most light paths a pilot traces (a few seconds; it holds a record of each), and the
/// most camera samples of a trial.
const MAX_PILOT: u32 = 1 << 22;

/// The lp_lt integrator: `camera`'s paths joined to the suns' light paths.
pub struct LpLt {
    camera: PathTracer<PortalNextEvent>,
    options: LightPathOptions,
    /// The suns' light paths (set when prepared; `None` when there are none to trace).
    suns: Option<Arc<SunPaths>>,
    /// [`SunPaths::sunlight_through_portals`], once measured.
    sunlight_through_portals: Option<f64>,
    /// The trial that decided whether light paths pay, once run.
    trial: Option<Trial>,
}

impl LpLt {
    /// The light paths of `uniform` started where a pilot of them (if asked for) found them
    /// to bring light to `film`, and the pilot's rays and counts; `None` without a pilot, or
    /// when no pilot path brought any light.
    fn learn(
        &self,
        scene: &RenderScene,
        film: &Film,
        settings: &RenderSettings,
        uniform: &LightPasses,
    ) -> Option<(SunPaths, RenderStats)> {
        if self.options.pilot == 0 {
            return None;
        }
        let (started, mut pilot) = (std::time::Instant::now(), RenderStats::default());
        let size = (film.window.full_width, film.window.full_height);
        let tally = uniform.pilot(
            scene,
            size,
            settings.seed,
            self.options.pilot,
            &mut pilot.rays,
        );
        if tally.contributing == 0 {
            return None;
        }
        let extra = &mut pilot.extra;
        extra.insert("emission_pilot_paths".into(), f64::from(self.options.pilot));
        extra.insert("emission_contributing".into(), tally.contributing as f64);
        extra.insert("emission_pilot_s".into(), started.elapsed().as_secs_f64());
        Some((uniform.suns.learned(&tally), pilot))
    }
}

/// Light paths start at the portals, so where these take less of the sunlight on what the
/// camera sees than this, lp_lt traces none: on Sponza the estimated portals (an opening in
/// the courtyard's side) took 0% of it, the sun falling through the roof, and light paths
/// through them brought 0.7% of the image's light for a quarter of the camera samples; on
/// the four rooms where they paid, 88-100% (docs/interiors.md).
const MIN_SUNLIGHT_THROUGH_PORTALS: f64 = 0.25;

impl LpLt {
    /// How many times as efficient the trial measured the render with light paths as
    /// without them, once it ran.
    pub fn trial_gain(&self) -> Option<f64> {
        self.trial.map(|t| t.gain())
    }

    /// Runs the trial of light paths (`camera` joined to `suns`, and again alone), or `None`
    /// when cancelled; leaves the camera joined.
    fn try_light_paths(
        &mut self,
        scene: &RenderScene,
        suns: &Arc<SunPaths>,
        control: &RenderControl,
    ) -> Option<Trial> {
        let (started, size) = (
            Instant::now(),
            trial::size(control.image_size, self.options.trial),
        );
        let per_sample = self.options.per_sample;
        let passes = |camera| LightPasses::new(Some(camera), suns, camera.options(), per_sample);
        let joined = trial::joined(passes(&self.camera), scene, size, control)?;
        self.camera.join_light_paths(None);
        let alone = LightPasses::new(Some(&self.camera), suns, self.camera.options(), 0.0);
        let alone = trial::alone(alone, scene, size, control);
        self.camera.join_light_paths(Some(suns.clone()));
        Some(Trial::of(joined, alone?, started.elapsed().as_secs_f64()))
    }

    /// lp_hf's path tracer `camera` joined to light paths as `options` says.
    pub fn new(
        camera: PathTracer<PortalNextEvent>,
        options: LightPathOptions,
    ) -> Result<Self, OptionError> {
        options.check()?;
        Ok(LpLt {
            camera,
            options,
            suns: None,
            sunlight_through_portals: None,
            trial: None,
        })
    }
}

impl Integrator for LpLt {
    fn name(&self) -> &str {
        "lp_lt"
    }

    fn settings(&self) -> serde_json::Value {
        let mut s = self.camera.settings();
        if let Some(all) = s.as_object_mut() {
            let traced = self.suns.as_ref().map_or(0, |s| s.len());
            all.insert(
                "light_paths".into(),
                serde_json::json!({
                    "per_sample": self.options.per_sample,
                    "pilot": self.options.pilot,
                    "trial": self.options.trial,
                    "suns": traced,
                }),
            );
        }
        s
    }

    fn prepare(
        &mut self,
        scene: &RenderScene,
        control: &RenderControl,
    ) -> Result<(), IntegratorError> {
        self.camera.prepare(scene, control)?;
        let portals = self.camera.next_event().found_portals();
        if portals.is_empty() || self.options.per_sample == 0.0 {
            control.progress.note(
                "light paths: none to trace (no portal, or none asked for); lp_lt renders as lp_hf",
            );
            return Ok(());
        }
        let suns = match suns_through(scene, portals, "lp_lt", self.options.per_sample) {
            Ok(suns) => suns,
            Err(why) => {
                control.progress.note(&format!(
                    "light paths: none ({why}); lp_lt renders as lp_hf"
                ));
                return Ok(());
            }
        };
        self.sunlight_through_portals = suns.sunlight_through_portals(scene);
        if let Some(share) = self.sunlight_through_portals {
            if share < MIN_SUNLIGHT_THROUGH_PORTALS {
                control.progress.note(&format!(
                    "light paths: none: the portals take {:.0}% of the sunlight on what the \
                     camera sees, and light paths start at them; lp_lt renders as lp_hf",
                    100.0 * share
                ));
                return Ok(());
            }
        }
        let suns = Arc::new(suns);
        self.camera.join_light_paths(Some(suns.clone()));
        if self.options.trial > 0 {
            let Some(trial) = self.try_light_paths(scene, &suns, control) else {
                self.camera.join_light_paths(None); // cancelled: the render stops at once
                return Ok(());
            };
            self.trial = Some(trial);
            let (gain, rays) = (
                trial.gain(),
                trial.with.rays as f64 / trial.without.rays as f64,
            );
            let measured = format!(
                "light paths: a trial of {} camera samples measured {gain:.2}x the efficiency \
                 without them ({rays:.2}x the rays)",
                self.options.trial
            );
            if !(gain > 1.0) {
                self.camera.join_light_paths(None);
                control.progress.note(&format!(
                    "{measured}; lp_lt renders as lp_hf (--light-paths-trial 0 traces them)"
                ));
                return Ok(());
            }
            control.progress.note(&measured);
        }
        self.suns = Some(suns);
        Ok(())
    }

    /// Light paths splat anywhere in the image, so a tile would miss what other tiles' light
    /// paths bring to its pixels; sample ranges merge (each sample's light paths are its own,
    /// and the film-state file keeps their splats).
    fn split(&self) -> Split {
        Split::Samples
    }

    fn render(
        &self,
        scene: &RenderScene,
        film: &mut Film,
        settings: &RenderSettings,
        control: &RenderControl,
    ) -> RenderStats {
        let mut stats = match &self.suns {
            None => self.camera.render(scene, film, settings, control),
            Some(suns) => {
                let (options, per_sample) = (self.camera.options(), self.options.per_sample);
                let camera = Some(&self.camera);
                let mut uniform = LightPasses::new(camera, suns, options, per_sample);
                match self.learn(scene, film, settings, &uniform) {
                    None => uniform.render(scene, film, settings, control),
                    Some((learned, mut pilot)) => {
                        control.progress.note(&format!(
                            "light paths: where they start learned from {} pilot paths ({} \
                             brought light)",
                            self.options.pilot, pilot.extra["emission_contributing"]
                        ));
                        let mut passes = LightPasses::new(camera, &learned, options, per_sample);
                        let mut stats = passes.render(scene, film, settings, control);
                        stats.rays += pilot.rays;
                        stats.extra.append(&mut pilot.extra);
                        stats
                    }
                }
            }
        };
        if let Some(share) = self.sunlight_through_portals {
            stats.extra.insert("sunlight_through_portals".into(), share);
        }
        if let Some(trial) = self.trial {
            stats
                .extra
                .insert("light_paths_trial_gain".into(), trial.gain());
            stats
                .extra
                .insert("light_paths_trial_s".into(), trial.seconds);
        }
        stats
    }
}
