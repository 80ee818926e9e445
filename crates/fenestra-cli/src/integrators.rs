//! The integrators this binary offers, each built from its own option group: the path
//! tracers of fenestra-render and the research crates' integrators (lp_hf from
//! fenestra-portals). A new integrator is one `register` call and, if it has options, one
//! option group here.

use crate::portals_cmd::EstimateOpts;
use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use fenestra_cache::{GlossyCache, Gradients, Sdrc, SdrcOptions};
use fenestra_core::mis::MisHeuristic;
use fenestra_eval::hash::debug_hash;
use fenestra_eval::suite::slug;
use fenestra_manylights::ias::{BsdfSamples, Combine};
use fenestra_manylights::learned::Base;
use fenestra_manylights::{Ias, IasOptions, LearnedLights, LearnedOptions, LightBvh};
use fenestra_portals::estimate::Model;
use fenestra_portals::{PortalChoice, PortalOptions, PortalSampling, PortalSource, Portals};
use fenestra_render::integrator::{hf, IntegratorError, LightNextEvent, PathOptions, PathTracer};
use fenestra_render::light::LightSelection;
use fenestra_render::{Registry, RenderScene};
use fenestra_scene::SceneDesc;
use std::path::{Path, PathBuf};

/// Which integrator, and every integrator's options.
#[derive(Args, Clone, Debug)]
pub struct IntegratorArgs {
    /// Integrator (`fenestra list` shows them): hf (BSDF sampling), af_hf (light and BSDF
    /// sampling with MIS), lp_hf (light-portal and BSDF sampling with MIS), ias (adaptive
    /// direct light for many lights), sdrc (af_hf with cached indirect light on glossy
    /// surfaces) or shrc (the same with SH radiance caching).
    #[arg(long, default_value = "af_hf")]
    pub integrator: String,
    #[command(flatten, next_help_heading = "Path tracing (hf, af_hf, lp_hf)")]
    pub path: PathArgs,
    #[command(flatten, next_help_heading = "Light sampling (af_hf, lp_hf)")]
    pub lights: LightArgs,
    #[command(flatten, next_help_heading = "Light portals (lp_hf)")]
    pub portals: PortalArgs,
    #[command(
        flatten,
        next_help_heading = "Iterative adaptive sampling (ias, ias_reference)"
    )]
    pub ias: IasArgs,
    #[command(flatten, next_help_heading = "Radiance caching (sdrc, shrc)")]
    pub sdrc: SdrcArgs,
}

/// Options of sdrc (seed 003 ch. 2).
#[derive(Args, Clone, Debug)]
pub struct SdrcArgs {
    /// Maximum interpolation error a of SDRC records (eq. 2.1; smaller: more records).
    #[arg(long, default_value_t = 0.22)]
    sdrc_a: f32,
    /// Factor on a in the render passes (the seed's 1.3: smoother interpolation).
    #[arg(long, default_value_t = 1.3)]
    sdrc_a_scale: f32,
    /// Rays traced to create a record (the seed's N).
    #[arg(long, default_value_t = 256)]
    sdrc_n: u32,
    /// BRDF-sampled directions per shading point (the seed's M; it took N ~ 12 M with 4
    /// samples per pixel, fenestra takes more samples and fewer directions each).
    #[arg(long, default_value_t = 2)]
    sdrc_m: u32,
    /// Largest radius of a directional query in the paraboloid disc (the seed's r_max).
    #[arg(long, default_value_t = 0.15)]
    sdrc_r_max: f32,
    /// Samples of a record a directional query expects at the least: its radius shrinks as a
    /// pixel averages more directions, down to the radius that holds this many of the
    /// record's N (0: it shrinks on, each query then finding one sample or none).
    #[arg(long, default_value_t = 5.0)]
    sdrc_query_samples: f32,
    /// Smallest reach of a record, in pixels at its point of the view 256 pixels across
    /// (larger images scale it with their larger side: 10 pixels at 640x360, 20 at 1280x720,
    /// so records resolve the same scene detail at any size; 0: as small as eq. 2.2 makes it).
    #[arg(long, default_value_t = 4.0)]
    sdrc_min_reach: f32,
    /// Indirect light on diffuse surfaces: cache (an irradiance cache with gradients, as the
    /// seed) or path (path tracing, as af_hf).
    #[arg(long, value_enum, default_value = "cache")]
    sdrc_diffuse: CacheOrPath,
    /// sdrc: indirect light on glossy surfaces: cache (SDRC) or path (path tracing by BSDF
    /// sampling with everything else as sdrc: the seed's Monte Carlo baseline).
    #[arg(long, value_enum, default_value = "cache")]
    sdrc_glossy: CacheOrPath,
    /// Rays per irradiance-cache record (stratified over rings and sectors).
    #[arg(long, default_value_t = 1024)]
    sdrc_irradiance_rays: u32,
    /// Gradients that extrapolate irradiance records: none, rotation, or both (rotation and
    /// translation; the translation gradient of path-traced radiance is mostly noise).
    #[arg(long, value_enum, default_value = "rotation")]
    sdrc_irradiance_gradients: IrradianceGradients,
    /// Maximum interpolation error of the irradiance cache (Ward's a).
    #[arg(long, default_value_t = 0.15)]
    sdrc_irradiance_a: f32,
    /// Where the Lambertian lobe of a glossy material (Phong's and Ward's kd) takes its
    /// indirect light: glossy (the glossy cache, with the glossy lobe) or cache (the
    /// irradiance cache, with --sdrc-diffuse cache; docs/sdrc.md measures both).
    #[arg(long, value_enum, default_value = "glossy")]
    sdrc_lambertian_lobe: LambertianLobe,
    /// Photons emitted for the light beyond the records' rays, which then end at diffuse
    /// surfaces in a photon-map estimate (the seed's setting); 0: their paths are traced on.
    #[arg(long, default_value_t = 0)]
    sdrc_photons: u32,
    /// Photons per radiance estimate (the k nearest).
    #[arg(long, default_value_t = 50)]
    sdrc_photon_k: u32,
    /// Largest photon gather radius, as a fraction of the scene's bounding-sphere radius.
    #[arg(long, default_value_t = 0.03)]
    sdrc_photon_radius: f32,
    /// shrc: maximum interpolation error a of SH records (the seed's 0.25).
    #[arg(long, default_value_t = 0.25)]
    shrc_a: f32,
    /// shrc: rays per SH record, stratified uniformly over the hemisphere.
    #[arg(long, default_value_t = 1024)]
    shrc_rays: u32,
}

impl SdrcArgs {
    /// The options of sdrc (or, with `glossy`, of shrc) as given.
    fn options(&self, glossy: GlossyCache) -> SdrcOptions {
        SdrcOptions {
            a: self.sdrc_a,
            a_scale: self.sdrc_a_scale,
            n: self.sdrc_n,
            m: self.sdrc_m,
            r_max: self.sdrc_r_max,
            query_samples: self.sdrc_query_samples,
            min_reach: self.sdrc_min_reach,
            diffuse: matches!(self.sdrc_diffuse, CacheOrPath::Cache),
            irradiance_rays: self.sdrc_irradiance_rays,
            irradiance_a: self.sdrc_irradiance_a,
            irradiance_gradients: match self.sdrc_irradiance_gradients {
                IrradianceGradients::None => Gradients::None,
                IrradianceGradients::Rotation => Gradients::Rotation,
                IrradianceGradients::Both => Gradients::Both,
            },
            glossy,
            split: matches!(self.sdrc_lambertian_lobe, LambertianLobe::Cache),
            photons: self.sdrc_photons,
            photon_k: self.sdrc_photon_k,
            photon_radius: self.sdrc_photon_radius,
        }
    }
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum IrradianceGradients {
    None,
    Rotation,
    Both,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum LambertianLobe {
    Cache,
    Glossy,
}

/// Whether a kind of surface takes its indirect light from a cache or from path tracing.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum CacheOrPath {
    Cache,
    Path,
}

/// Options of ias (seed 004).
#[derive(Args, Clone, Debug)]
pub struct IasArgs {
    /// Relative variance at which a pixel is done (the seed's t; 1e-3 is a relative standard
    /// error of about 3%).
    #[arg(long, default_value_t = 1e-3)]
    ias_threshold: f32,
    /// Most passes per 8x8 block.
    #[arg(long, default_value_t = 15)]
    ias_max_passes: u32,
    /// Largest solid angle of a light cluster in a cut, in steradians.
    #[arg(long, default_value_t = 0.02)]
    ias_solid_angle: f32,
    /// How a pixel's passes are combined: samples (every shadow ray after pass 0, which only
    /// seeds the statistics, weighs the same; unbiased) or inverse-variance (the seed's eq.
    /// 3.3-3.4, every pass; slightly dark).
    #[arg(long, value_enum, default_value = "samples")]
    ias_combine: IasCombine,
    /// Regions an environment is cut into, each a cluster of the cuts (the seed's 300; 0
    /// takes the environment whole).
    #[arg(long, default_value_t = 300)]
    ias_sky_regions: usize,
    /// Most eye rays a pixel takes while what they see emitted varies (the edge of a light
    /// seen directly), until its mean is within --ias-threshold; 0 keeps the seed's counts
    /// (25 per surface at up to 512x512, up to three surfaces).
    #[arg(long, default_value_t = fenestra_manylights::ias::EMITTED_RAYS)]
    ias_emitted_rays: u32,
    /// Which points take a BSDF sample with each light sample, the two weighed by MIS: auto
    /// (where a light of the point's cut subtends more than the BSDF's lobe: a polished floor
    /// mirroring a window, a wall beside a large emitter), all, or none (light samples only,
    /// and mirrors and glass show only what they see emitted: the seed). With auto and all,
    /// eye rays follow mirrors and glass one bounce on.
    #[arg(long, value_enum, default_value = "auto")]
    ias_bsdf_samples: IasBsdfSamples,
    /// Most eye-ray hits of an anti-aliasing region that its light samples take in turn, so
    /// that the region's estimate is of the whole region and not of its first hit (1: the
    /// first hit stands for the region, as the seed).
    #[arg(long, default_value_t = fenestra_manylights::ias::REGION_HITS)]
    ias_region_hits: u32,
    /// Eye rays, in units of the seed's per surface, that a pixel takes at least when a
    /// neighbour's rays saw the edge of a light and its own did not (it may hold a sliver of
    /// the light they missed); 0 leaves such pixels their own counts.
    #[arg(long, default_value_t = fenestra_manylights::ias::EDGE_RAYS)]
    ias_edge_rays: u32,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum IasBsdfSamples {
    Auto,
    All,
    None,
}

impl IasBsdfSamples {
    fn mode(self) -> BsdfSamples {
        match self {
            IasBsdfSamples::Auto => BsdfSamples::Auto,
            IasBsdfSamples::All => BsdfSamples::All,
            IasBsdfSamples::None => BsdfSamples::None,
        }
    }
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum IasCombine {
    Samples,
    InverseVariance,
}

#[derive(Clone, Copy, ValueEnum, Debug)]
enum Mis {
    Balance,
    Power,
}

/// Options of the path tracers.
#[derive(Args, Clone, Debug)]
pub struct PathArgs {
    /// Maximum path length in segments from the camera to the emitter (2 = direct light only;
    /// default: the scene's).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// MIS heuristic combining BSDF sampling with the next-event strategy.
    #[arg(long, value_enum, default_value = "power")]
    mis: Mis,
    /// Exponent of the power heuristic.
    #[arg(long, default_value_t = 2.0)]
    beta: f32,
    /// Path length from which Russian roulette may end paths.
    #[arg(long, default_value_t = 3)]
    rr_depth: u32,
}

/// Options of light sampling.
#[derive(Args, Clone, Debug)]
pub struct LightArgs {
    /// How next-event estimation picks a light: power (in proportion to emitted power),
    /// uniform, all (a sample of every light in each estimate; beyond 8 lights, of one light
    /// in each of 8 groups of about equal power), bvh (a light tree that weighs lights by
    /// their power, distance and orientation at each point), or learned (the tree mixed with
    /// what the first passes learn about which lights each region of the scene actually
    /// sees).
    #[arg(long, value_enum, default_value = "power")]
    light_selection: LightChoice,
    /// With --light-selection bvh: adaptive splitting. Near the top of the tree, a node whose
    /// box the point sees with 1/d^2 varying by more than this factor gets a light sample for
    /// each child (up to 8 per estimate) instead of a choice between them; 0 never splits.
    #[arg(long, default_value_t = 0.0)]
    bvh_split: f32,
    /// With --light-selection learned: the share of light samples drawn from what was
    /// learned (the rest by the light tree, which keeps every light that can reach a point
    /// samplable).
    #[arg(long, default_value_t = LearnedOptions::default().mix)]
    learned_mix: f32,
    /// With --light-selection learned: light samples of the first pass per cell, on average.
    /// Cells (boxes, six normal directions each) learn which lights they see; this sets their
    /// size, which thus follows the image's resolution and what the camera sees.
    #[arg(long, default_value_t = LearnedOptions::default().cell_records)]
    learned_cell_records: u32,
    /// With --light-selection learned: groups of lights (a cut through the light tree) whose
    /// shares each cell learns.
    #[arg(long, default_value_t = LearnedOptions::default().groups)]
    learned_groups: usize,
    /// With --light-selection learned: passes learned from (passes take 1, 2, 4, ... samples
    /// per pixel; the later passes use what the last one learned).
    #[arg(long, default_value_t = LearnedOptions::default().passes)]
    learned_passes: u32,
    /// With --light-selection learned: what the rest of the light samples are drawn by where
    /// a cell has learned something: bvh (the light tree) or power (emitted power, which costs
    /// almost nothing).
    #[arg(long, value_enum, default_value = "bvh")]
    learned_base: LearnedBase,
}

/// The distributions learned ones are mixed with.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum LearnedBase {
    Bvh,
    Power,
}

/// The light samplers on offer.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum LightChoice {
    Power,
    Uniform,
    All,
    Bvh,
    Learned,
}

impl LightArgs {
    /// Whether a next-event estimate takes several lights.
    fn splits(&self) -> bool {
        self.bvh_split > 0.0 || matches!(self.light_selection, LightChoice::All)
    }

    /// Light sampling with the chosen light sampler (af_hf's next event; lp_hf's for its share
    /// of light sampling and for Dirac lights); `learns`: whether the integrator lets a
    /// learned sampler learn from its passes.
    fn next_event(&self, learns: bool) -> Result<LightNextEvent, IntegratorError> {
        if !(self.bvh_split.is_finite() && self.bvh_split >= 0.0) {
            return Err(IntegratorError::Options(format!(
                "--bvh-split must be 0 (off) or a positive factor, got {}",
                self.bvh_split
            )));
        }
        if self.bvh_split > 0.0 && !matches!(self.light_selection, LightChoice::Bvh) {
            return Err(IntegratorError::Options(
                "--bvh-split splits the light BVH: use it with --light-selection bvh".into(),
            ));
        }
        Ok(match self.light_selection {
            LightChoice::Power => LightNextEvent::new(LightSelection::Power),
            LightChoice::Uniform => LightNextEvent::new(LightSelection::Uniform),
            LightChoice::All => LightNextEvent::new(LightSelection::All),
            LightChoice::Bvh if self.bvh_split > 0.0 => {
                let split = self.bvh_split;
                LightNextEvent::with_sampler(
                    format!("bvh(split {split})"),
                    move |s: &RenderScene| {
                        Box::new(LightBvh::new(&s.scene, &s.lights).with_splitting(split))
                    },
                )
            }
            LightChoice::Bvh => LightNextEvent::with_sampler("bvh", |s: &RenderScene| {
                Box::new(LightBvh::new(&s.scene, &s.lights))
            }),
            LightChoice::Learned => {
                if !learns {
                    return Err(IntegratorError::Options(
                        "--light-selection learned learns from the passes of af_hf and lp_hf; \
                         this integrator takes power, uniform or bvh"
                            .into(),
                    ));
                }
                let options = LearnedOptions {
                    groups: self.learned_groups,
                    cell_records: self.learned_cell_records,
                    mix: self.learned_mix,
                    passes: self.learned_passes,
                    base: match self.learned_base {
                        LearnedBase::Bvh => Base::Bvh,
                        LearnedBase::Power => Base::Power,
                    },
                };
                options.check().map_err(IntegratorError::Options)?;
                LightNextEvent::with_learning_sampler(options.name(), move |s: &RenderScene| {
                    Box::new(LearnedLights::new(&s.scene, &s.lights, options))
                })
            }
        })
    }
}

/// Options of lp_hf.
#[derive(Args, Clone, Debug)]
pub struct PortalArgs {
    /// Light portals: a portals.json file, or "auto" to estimate them first with the default
    /// parameters of `fenestra portals` (default: the scene's own portals).
    #[arg(long)]
    pub portals: Option<String>,
    /// How a point is chosen on a portal: solid-angle (rectangles by the solid angle they
    /// subtend, Urena et al. 2013, where area sampling would spread the density of
    /// directions by more than 3x) or area (seed 000 eq. 4.1).
    #[arg(long, default_value = "solid-angle")]
    portal_sampling: PortalSampling,
    /// How a portal is picked: contribution (solid angle times cosine at the point), facing
    /// (uniform among those not behind the surface, as Cycles) or uniform (the seed's).
    #[arg(long, default_value = "contribution")]
    portal_choice: PortalChoice,
    /// Probability that a sample comes from light sampling instead of the portals (Cycles
    /// mixes its portals with environment sampling; 0 uses the portals only).
    #[arg(long, default_value_t = 0.0)]
    portal_light_mix: f32,
    /// With --portals auto: the shape fitted to each cluster (smallest, ellipse, rectangle or
    /// pca; see `fenestra portals --model`).
    #[arg(long, default_value = "smallest")]
    portal_model: Model,
    /// With --portals auto: the folder where estimated portals are kept, by scene content and
    /// parameters, so that the next render of the same scene reads them instead of estimating
    /// again (default: $XDG_CACHE_HOME/fenestra/portals, else ~/.cache/fenestra/portals).
    #[arg(long)]
    portal_cache: Option<PathBuf>,
    /// With --portals auto: estimate every time and cache nothing.
    #[arg(long, conflicts_with = "portal_cache")]
    no_portal_cache: bool,
}

impl PathArgs {
    /// The path tracers' options, with the scene's path length unless one is given.
    pub fn options(&self, scene_max_depth: u32) -> Result<PathOptions> {
        if self.max_depth == Some(0) {
            bail!("--max-depth must be at least 1 (1 = emitters seen directly, 2 = direct light)");
        }
        if !(self.beta.is_finite() && self.beta > 0.0) {
            bail!("--beta must be positive, got {}", self.beta);
        }
        Ok(PathOptions {
            max_depth: self.max_depth.unwrap_or(scene_max_depth),
            mis: match self.mis {
                Mis::Balance => MisHeuristic::Balance,
                Mis::Power => MisHeuristic::Power { beta: self.beta },
            },
            rr_depth: self.rr_depth,
        })
    }
}

impl PortalArgs {
    /// lp_hf's options for `scene`: the portals file is read here, before the scene is built.
    fn options(&self, scene: &SceneDesc) -> Result<PortalOptions, IntegratorError> {
        let source = match self.portals.as_deref() {
            None => PortalSource::Scene,
            Some("auto") => {
                let params = EstimateOpts::defaults_with(self.portal_model);
                let cache = self.cache_folder().map(|dir| {
                    let key = debug_hash(&(
                        scene,
                        serde_json::to_string(&params).ok(),
                        env!("CARGO_PKG_VERSION"),
                    ));
                    dir.join(format!("{}-{key:016x}.json", slug(&scene.name)))
                });
                PortalSource::Estimated { params, cache }
            }
            Some(file) => PortalSource::Given(Portals::read_json(Path::new(file))?),
        };
        Ok(PortalOptions {
            source,
            sampling: self.portal_sampling,
            choice: self.portal_choice,
            light_mix: self.portal_light_mix,
        })
    }

    /// Where estimated portals are cached, unless --no-portal-cache.
    fn cache_folder(&self) -> Option<PathBuf> {
        if self.no_portal_cache {
            return None;
        }
        if let Some(dir) = &self.portal_cache {
            return Some(dir.clone());
        }
        let base = std::env::var_os("XDG_CACHE_HOME")
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
        Some(base.join("fenestra/portals"))
    }
}

/// What an integrator is built from: the path tracers' options (resolved against the
/// scene) and every option group as given.
pub struct Config<'a> {
    /// Path tracing options.
    pub path: PathOptions,
    /// Everything from the command line.
    pub args: &'a IntegratorArgs,
    /// The scene to be rendered (keys caches by its content).
    pub scene: &'a SceneDesc,
}

/// Every integrator of this binary.
pub fn registry<'a>() -> Registry<Config<'a>> {
    Registry::new()
        .register(
            "hf",
            "plain path tracing: follows the surfaces' reflection only (seed 000's HF)",
            |c: &Config| Ok(Box::new(hf(c.path))),
        )
        .register(
            "af_hf",
            "path tracing that also aims at the lights, the usual default (seed 000's AF_HF)",
            |c: &Config| {
                Ok(Box::new(PathTracer::new(
                    "af_hf",
                    c.args.lights.next_event(true)?,
                    c.path,
                )))
            },
        )
        .register(
            "ias",
            "direct light for scenes with many lights, learnt block by block in passes until each pixel is within a set noise (seed 004)",
            |c: &Config| {
                let a = &c.args.ias;
                Ok(Box::new(Ias::new(IasOptions {
                    threshold: a.ias_threshold,
                    max_passes: a.ias_max_passes,
                    solid_angle: a.ias_solid_angle,
                    combine: match a.ias_combine {
                        IasCombine::Samples => Combine::Samples,
                        IasCombine::InverseVariance => Combine::InverseVariance,
                    },
                    sky_regions: a.ias_sky_regions,
                    emitted_rays: a.ias_emitted_rays,
                    bsdf_samples: a.ias_bsdf_samples.mode(),
                    region_hits: a.ias_region_hits,
                    edge_rays: a.ias_edge_rays,
                    ..IasOptions::default()
                })?))
            },
        )
        .register(
            "ias_reference",
            "the reference seed 004 measures ias against: lights picked by unoccluded irradiance, rays until each pixel is within --ias-threshold",
            |c: &Config| {
                let a = &c.args.ias;
                Ok(Box::new(Ias::new(IasOptions {
                    emitted_rays: a.ias_emitted_rays,
                    bsdf_samples: a.ias_bsdf_samples.mode(),
                    region_hits: a.ias_region_hits,
                    edge_rays: a.ias_edge_rays,
                    ..IasOptions::reference(a.ias_threshold)
                })?))
            },
        )
        .register(
            "sdrc",
            "af_hf with the first bounce of indirect light on glossy surfaces cached and interpolated (spatial directional radiance caching, seed 003)",
            |c: &Config| {
                let options = c.args.sdrc.options(match c.args.sdrc.sdrc_glossy {
                    CacheOrPath::Cache => GlossyCache::Directional,
                    CacheOrPath::Path => GlossyCache::Path,
                });
                Ok(Box::new(Sdrc::new(options, c.path, c.args.lights.next_event(false)?)?))
            },
        )
        .register(
            "shrc",
            "sdrc's baseline: the same, with spherical-harmonic radiance caching (order 10) on glossy surfaces (Krivanek et al. 2005)",
            |c: &Config| {
                if let CacheOrPath::Path = c.args.sdrc.sdrc_glossy {
                    return Err(IntegratorError::Options(
                        "--sdrc-glossy path leaves glossy surfaces to path tracing: use it with \
                         --integrator sdrc (shrc caches them)"
                            .into(),
                    ));
                }
                let rays = c.args.sdrc.shrc_rays;
                let options = SdrcOptions {
                    a: c.args.sdrc.shrc_a,
                    ..c.args.sdrc.options(GlossyCache::Harmonics { rays })
                };
                Ok(Box::new(Sdrc::new(options, c.path, c.args.lights.next_event(false)?)?))
            },
        )
        .register(
            "lp_hf",
            "path tracing that aims through windows and openings (light portals; seed 000's LP_HF)",
            |c: &Config| {
                let options = c.args.portals.options(c.scene)?;
                if options.light_mix > 0.0 && c.args.lights.splits() {
                    return Err(IntegratorError::Options(
                        "--portal-light-mix draws one light at a time: not with --bvh-split \
                         or --light-selection all, whose estimates take several"
                            .into(),
                    ));
                }
                Ok(Box::new(fenestra_portals::lp_hf(
                    c.path,
                    options,
                    c.args.lights.next_event(true)?,
                )?))
            },
        )
}

impl IntegratorArgs {
    /// Refuses options that belong to an integrator other than the one chosen.
    pub fn check(&self) -> Result<()> {
        if let (Some(p), false) = (&self.portals.portals, self.integrator == "lp_hf") {
            bail!("--portals {p} is for --integrator lp_hf");
        }
        Ok(())
    }
}
