//! The SCENE argument and the flags that say how it is lit, made into the session's typed
//! scene request: `builtin:NAME`, a pbrt-v4 file, a glTF 2.0 scene, or an OBJ/PLY mesh.

use anyhow::{anyhow, bail, Result};
use fenestra_scene::sky::solar_position::Moment;
use fenestra_session::scene::axis_named;
use fenestra_session::{Lighting, LoadedScene, Placement, SceneRequest, SkyRequest, SunPlace};
use std::path::PathBuf;

/// How scene files are read.
#[derive(clap::Args, Clone, Debug)]
pub struct SceneOptions {
    /// Refuse scene files that use anything fenestra does not support (instead of warning).
    #[arg(long)]
    pub strict: bool,
    /// Light the scene by this environment map instead of its own environment (its other
    /// lights stay): a 2:1 latitude-longitude image (EXR, HDR or PFM; row 0 the zenith),
    /// importance-sampled like any environment.
    #[arg(long, value_name = "FILE")]
    pub environment: Option<PathBuf>,
    /// Light the scene by a physical clear sky and its sun (Hosek-Wilkie 2012 sky, SPECTRL2
    /// sun disk of 0.53 degrees) instead of its own environment (its other lights stay).
    #[arg(long, conflicts_with = "environment")]
    pub sky: bool,
    /// --sky's atmospheric turbidity: 1 (arctic clear) to 10 (hazy); 3 is a clear temperate
    /// day.
    #[arg(long, value_name = "T", default_value_t = SkyRequest::default().turbidity, requires = "sky")]
    pub sky_turbidity: f32,
    /// --sky's ground albedo (in the sky model, and the ground below the horizon).
    #[arg(long, value_name = "ALBEDO", default_value_t = SkyRequest::default().albedo, requires = "sky")]
    pub sky_albedo: f32,
    /// --sky's sun: elevation above the horizon and azimuth clockwise from north, in degrees
    /// (north is the environment's phi = 0 direction, turned by --environment-rotation)
    /// [default: 45,180].
    #[arg(
        long,
        value_name = "ELEVATION,AZIMUTH",
        requires = "sky",
        conflicts_with = "sun_time",
        allow_hyphen_values = true
    )]
    pub sun: Option<String>,
    /// --sky's sun where it stands at this moment (RFC 3339 with its UTC offset, e.g.
    /// 2026-06-21T15:30+02:00) seen from --location.
    #[arg(long, value_name = "DATETIME", requires_all = ["sky", "location"])]
    pub sun_time: Option<String>,
    /// Where --sun-time's sun is seen from: latitude (north positive) and longitude (east
    /// positive), in degrees.
    #[arg(
        long,
        value_name = "LATITUDE,LONGITUDE",
        requires = "sun_time",
        allow_hyphen_values = true
    )]
    pub location: Option<String>,
    /// Multiply --sky's sun (its disk's radiance) by this, on top of --environment-strength;
    /// 0 leaves the sky without its sun (as Blender's Hosek-Wilkie and Preetham skies are)
    /// [default: 1].
    #[arg(
        long,
        value_name = "X",
        requires = "sky",
        allow_negative_numbers = true
    )]
    pub sun_strength: Option<f32>,
    /// Turn --environment or --sky about the up axis by this many degrees
    /// (counter-clockwise seen from above) [default: 0].
    #[arg(long, value_name = "DEGREES", allow_negative_numbers = true)]
    pub environment_rotation: Option<f32>,
    /// Multiply --environment's or --sky's radiance (and the sun's) by this [default: 1].
    #[arg(long, value_name = "X")]
    pub environment_strength: Option<f32>,
    /// The scene's up axis for --environment or --sky: x, y, z, -x, -y or -z [default: the
    /// axis nearest the camera's up].
    #[arg(long, value_name = "AXIS", allow_hyphen_values = true)]
    pub environment_up: Option<String>,
    /// A glTF scene's camera, by name or index (`fenestra scene info` lists them) [default:
    /// its first camera; a camera framing the scene in a file without one].
    #[arg(long, value_name = "NAME|INDEX")]
    pub camera: Option<String>,
}

impl Default for SceneOptions {
    /// The scene as its file describes it.
    fn default() -> Self {
        SceneOptions {
            strict: false,
            environment: None,
            sky: false,
            sky_turbidity: SkyRequest::default().turbidity,
            sky_albedo: SkyRequest::default().albedo,
            sun: None,
            sun_time: None,
            location: None,
            sun_strength: None,
            environment_rotation: None,
            environment_strength: None,
            environment_up: None,
            camera: None,
        }
    }
}

impl SceneOptions {
    /// The session's request for scene `source` lit as these flags say.
    pub fn request(&self, source: &str) -> Result<SceneRequest> {
        let placed = self.environment.is_some() || self.sky;
        let moved = self.environment_rotation.is_some()
            || self.environment_strength.is_some()
            || self.environment_up.is_some();
        if moved && !placed {
            bail!("--environment-rotation, --environment-strength and --environment-up place --environment or --sky; neither is given");
        }
        let up = match self.environment_up.as_deref() {
            None => None,
            Some(axis) => Some(axis_named(axis).ok_or_else(|| {
                anyhow!("--environment-up: expected x, y, z, -x, -y or -z, got \"{axis}\"")
            })?),
        };
        let placement = Placement {
            up,
            rotation_deg: self.environment_rotation.unwrap_or(0.0),
            strength: self.environment_strength.unwrap_or(1.0),
        };
        let lighting = match &self.environment {
            Some(path) => Lighting::Environment {
                path: path.clone(),
                placement,
            },
            None if self.sky => Lighting::Sky {
                sky: self.sky()?,
                placement,
            },
            None => Lighting::Own,
        };
        Ok(SceneRequest {
            source: source.to_string(),
            strict: self.strict,
            camera: self.camera.clone(),
            lighting,
        })
    }

    /// --sky's sky and sun.
    fn sky(&self) -> Result<SkyRequest> {
        let sun = match (&self.sun, &self.sun_time, &self.location) {
            (Some(sun), ..) => {
                let (elevation_deg, azimuth_deg) = pair(sun).ok_or_else(|| {
                    anyhow!(
                        "--sun: expected ELEVATION,AZIMUTH in degrees (e.g. 30,200), got \"{sun}\""
                    )
                })?;
                SunPlace::Angles {
                    elevation_deg,
                    azimuth_deg,
                }
            }
            (None, Some(time), Some(location)) => {
                let moment = Moment::parse(time).map_err(|e| anyhow!("--sun-time: {e}"))?;
                let (latitude, longitude) = pair(location).ok_or_else(|| {
                    anyhow!("--location: expected LATITUDE,LONGITUDE in degrees (latitude -90..90, longitude -180..180), got \"{location}\"")
                })?;
                SunPlace::At {
                    moment,
                    latitude,
                    longitude,
                }
            }
            _ => SkyRequest::default().sun,
        };
        Ok(SkyRequest {
            turbidity: self.sky_turbidity,
            albedo: self.sky_albedo,
            sun,
            sun_strength: self
                .sun_strength
                .unwrap_or(SkyRequest::default().sun_strength),
        })
    }
}

/// Loads `arg` as `opts` light it, printing warnings about unsupported input to stderr.
pub fn load(arg: &str, opts: &SceneOptions) -> Result<LoadedScene> {
    let loaded = load_quietly(arg, opts)?;
    for w in loaded.warnings() {
        eprintln!("warning: {w}");
    }
    Ok(loaded)
}

/// Loads `arg` as `opts` light it.
pub fn load_quietly(arg: &str, opts: &SceneOptions) -> Result<LoadedScene> {
    fenestra_session::load(&opts.request(arg)?).map_err(crate::flagged)
}

/// Two comma-separated numbers.
fn pair(text: &str) -> Option<(f32, f32)> {
    let (a, b) = text.split_once(',')?;
    let (a, b) = (a.trim().parse::<f32>().ok()?, b.trim().parse::<f32>().ok()?);
    (a.is_finite() && b.is_finite()).then_some((a, b))
}
