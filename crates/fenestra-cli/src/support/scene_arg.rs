//! Turning the SCENE argument into a scene description: `builtin:NAME`, a pbrt-v4 file, a
//! glTF 2.0 scene, or an OBJ/PLY mesh staged for viewing.

use anyhow::{bail, Context, Result};
use fenestra_builtin as builtin;
use fenestra_core::image::Image;
use fenestra_core::Vec3;
use fenestra_pbrt as pbrt;
use fenestra_scene::environment::EnvironmentMap;
use fenestra_scene::light::{EnvironmentDesc, LightDesc};
use fenestra_scene::sky::solar_position::{sun_position, Moment};
use fenestra_scene::sky::Sky;
use fenestra_scene::{mesh, SceneDesc};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// --sky's turbidity unless told: a clear temperate day.
pub const SKY_TURBIDITY: f32 = 3.0;
/// --sky's ground albedo unless told.
pub const SKY_ALBEDO: f32 = 0.3;

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
    #[arg(long, value_name = "T", default_value_t = SKY_TURBIDITY, requires = "sky")]
    pub sky_turbidity: f32,
    /// --sky's ground albedo (in the sky model, and the ground below the horizon).
    #[arg(long, value_name = "ALBEDO", default_value_t = SKY_ALBEDO, requires = "sky")]
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
            sky_turbidity: SKY_TURBIDITY,
            sky_albedo: SKY_ALBEDO,
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
    /// The environment's turn about the up axis (degrees).
    fn rotation_deg(&self) -> f32 {
        self.environment_rotation.unwrap_or(0.0)
    }

    /// The environment's strength.
    fn strength(&self) -> f32 {
        self.environment_strength.unwrap_or(1.0)
    }
}

/// A loaded scene with its load time, what it could not represent and the files it read.
pub struct LoadedScene {
    pub desc: SceneDesc,
    /// What a pbrt-v4 file asks for that fenestra replaces by something else.
    pub substitutions: Vec<pbrt::Warning>,
    /// What a pbrt-v4 file asks for that fenestra renders in its own documented way.
    pub notes: Vec<pbrt::Warning>,
    /// Other warnings: mesh files, a scene without light.
    pub other: Vec<String>,
    pub seconds: f64,
    /// Every file read (scene, includes, meshes, images): outputs must not replace them.
    pub files: Vec<PathBuf>,
    /// A glTF file's cameras by name, in index order (empty for other scenes).
    pub cameras: Vec<String>,
    /// The sky of --sky, with the strength it was given.
    pub sky: Option<(Sky, f32)>,
}

impl LoadedScene {
    /// Every warning as a line of text: substitutions, then the others.
    pub fn warnings(&self) -> Vec<String> {
        let subs = self.substitutions.iter().map(ToString::to_string);
        subs.chain(self.other.iter().cloned()).collect()
    }
}

/// Loads `arg`, printing warnings about unsupported input to stderr.
pub fn load(arg: &str, opts: &SceneOptions) -> Result<LoadedScene> {
    let loaded = load_quietly(arg, opts)?;
    for w in loaded.warnings() {
        eprintln!("warning: {w}");
    }
    Ok(loaded)
}

pub fn load_quietly(arg: &str, opts: &SceneOptions) -> Result<LoadedScene> {
    let start = Instant::now();
    let is_gltf = matches!(
        mesh::format_of(Path::new(arg)).as_deref(),
        Some("gltf" | "glb")
    );
    if opts.camera.is_some() && !is_gltf {
        bail!("--camera picks a glTF scene's camera; {arg} is not a .gltf or .glb file");
    }
    let (mut substitutions, mut notes, mut cameras) = (Vec::new(), Vec::new(), Vec::new());
    let (desc, warnings, files) = if let Some(name) = arg.strip_prefix("builtin:") {
        (builtin::load(name)?, Vec::new(), Vec::new())
    } else {
        let path = Path::new(arg);
        match mesh::format_of(path).as_deref() {
            Some("pbrt") => {
                let l = pbrt::load(path, opts.strict)?;
                (substitutions, notes) = (l.warnings, l.notes);
                (l.desc, Vec::new(), l.files)
            }
            Some("gltf" | "glb") => {
                let l = fenestra_gltf::load(path, opts.camera.as_deref())?;
                if opts.strict && !l.warnings.is_empty() {
                    bail!(
                        "{arg}: refused (--strict): {}",
                        l.warnings.join("; ")
                    );
                }
                let warnings = l.warnings.iter().map(|w| format!("{arg}: {w}")).collect();
                cameras = l.cameras;
                (l.desc, warnings, l.files)
            }
            Some("obj" | "ply") => {
                let (desc, warnings) = mesh::viewer_scene(path)?;
                let textures = desc
                    .materials
                    .iter()
                    .filter_map(|m| m.texture().map(|t| t.path.clone()));
                let files = std::iter::once(path.to_path_buf()).chain(textures).collect();
                (desc, warnings, files)
            }
            _ => bail!(
                "{arg}: unknown scene type (expected a .pbrt or .pbrt.gz file, a .gltf or .glb scene, an .obj or .ply mesh, or builtin:NAME; `fenestra list` shows the built-in scenes)"
            ),
        }
    };
    let placed = opts.environment.is_some() || opts.sky;
    let moved = opts.environment_rotation.is_some()
        || opts.environment_strength.is_some()
        || opts.environment_up.is_some();
    if moved && !placed {
        bail!("--environment-rotation, --environment-strength and --environment-up place --environment or --sky; neither is given");
    }
    let mut sky = None;
    let (desc, files) = match &opts.environment {
        Some(path) => (
            with_environment(desc, path, opts)?,
            [files, vec![path.clone()]].concat(),
        ),
        None if opts.sky => {
            let (desc, s) = with_sky(desc, opts)?;
            sky = Some((s, opts.strength()));
            (desc, files)
        }
        None => (desc, files),
    };
    let mut warnings = warnings;
    if desc.lights.is_empty() && desc.shapes.iter().all(|s| s.emission.is_none()) {
        warnings.push(format!(
            "{arg}: the scene has no light (no light source, no emissive shape): it renders black"
        ));
    }
    Ok(LoadedScene {
        desc,
        substitutions,
        notes,
        other: warnings,
        seconds: start.elapsed().as_secs_f64(),
        files,
        cameras,
        sky,
    })
}

/// `desc` lit by the environment map at `path` as `opts` place it.
fn with_environment(desc: SceneDesc, path: &Path, opts: &SceneOptions) -> Result<SceneDesc> {
    let image = Image::read(path).with_context(|| format!("--environment {}", path.display()))?;
    let map = EnvironmentMap {
        image: Arc::new(image),
        up: up_axis(&desc, opts)?,
        rotation_deg: opts.rotation_deg(),
        strength: opts.strength(),
    };
    if let Some(problem) = map.validate() {
        bail!("--environment {}: {problem}", path.display());
    }
    Ok(desc.with_environment(&map))
}

/// `desc` lit by the clear sky and sun `opts` describe, and that sky.
fn with_sky(desc: SceneDesc, opts: &SceneOptions) -> Result<(SceneDesc, Sky)> {
    let (elevation_deg, azimuth_deg) = match (&opts.sun, &opts.sun_time, &opts.location) {
        (Some(sun), ..) => pair(sun).ok_or_else(|| {
            anyhow::anyhow!(
                "--sun: expected ELEVATION,AZIMUTH in degrees (e.g. 30,200), got \"{sun}\""
            )
        })?,
        (None, Some(time), Some(location)) => {
            let moment = Moment::parse(time).map_err(|e| anyhow::anyhow!("--sun-time: {e}"))?;
            let (lat, lon) = pair(location)
                .filter(|(lat, lon)| lat.abs() <= 90.0 && lon.abs() <= 180.0)
                .ok_or_else(|| {
                    anyhow::anyhow!("--location: expected LATITUDE,LONGITUDE in degrees (latitude -90..90, longitude -180..180), got \"{location}\"")
                })?;
            let (el, az) = sun_position(&moment, lat as f64, lon as f64);
            if el < 0.0 {
                bail!("--sun-time {time} at {location}: the sun is {:.1} degrees below the horizon (the sky model covers a sun above it)", -el);
            }
            (el as f32, az as f32)
        }
        _ => (45.0, 180.0),
    };
    let sky = Sky {
        turbidity: opts.sky_turbidity,
        albedo: opts.sky_albedo,
        elevation_deg,
        azimuth_deg,
    };
    let up = up_axis(&desc, opts)?;
    let mut desc = (desc.with_sky(&sky, up, opts.rotation_deg(), opts.strength()))
        .map_err(|problem| anyhow::anyhow!("--sky: {problem}"))?;
    if let Some(k) = opts.sun_strength {
        if !(k.is_finite() && k >= 0.0) {
            bail!("--sun-strength must be 0 or more, got {k}");
        }
        desc.lights.retain_mut(|light| match light {
            LightDesc::Environment(EnvironmentDesc::Sun { radiance, .. }) => {
                *radiance *= k;
                k > 0.0
            }
            _ => true,
        });
    }
    Ok((desc, sky))
}

/// Two comma-separated numbers.
fn pair(text: &str) -> Option<(f32, f32)> {
    let (a, b) = text.split_once(',')?;
    let (a, b) = (a.trim().parse::<f32>().ok()?, b.trim().parse::<f32>().ok()?);
    (a.is_finite() && b.is_finite()).then_some((a, b))
}

/// The up axis `opts` give for `desc`'s environment.
fn up_axis(desc: &SceneDesc, opts: &SceneOptions) -> Result<Vec3> {
    match opts.environment_up.as_deref() {
        None => Ok(desc.camera_up_axis()),
        Some(axis) => axis_of(axis).ok_or_else(|| {
            anyhow::anyhow!("--environment-up: expected x, y, z, -x, -y or -z, got \"{axis}\"")
        }),
    }
}

/// A world axis by name (x, -y, ...).
fn axis_of(name: &str) -> Option<Vec3> {
    let (sign, axis) = match name.strip_prefix('-') {
        Some(axis) => (-1.0, axis),
        None => (1.0, name.strip_prefix('+').unwrap_or(name)),
    };
    let v = match axis {
        "x" => Vec3::X,
        "y" => Vec3::Y,
        "z" => Vec3::Z,
        _ => return None,
    };
    Some(v * sign)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sun's radiance in `builtin:box-hole` under `--sky` with `--sun-strength k`.
    fn sun_radiance(k: Option<f32>) -> Option<fenestra_core::Rgb> {
        let opts = SceneOptions {
            sky: true,
            sun_strength: k,
            ..SceneOptions::default()
        };
        let loaded = load_quietly("builtin:box-hole", &opts).expect("the scene under a sky");
        let mut suns = loaded.desc.lights.iter().filter_map(|l| match l {
            LightDesc::Environment(EnvironmentDesc::Sun { radiance, .. }) => Some(*radiance),
            _ => None,
        });
        let sun = suns.next();
        assert!(suns.next().is_none(), "one sun at most");
        sun
    }

    #[test]
    fn sun_strength_scales_the_sun_and_zero_takes_it_away() {
        let one = sun_radiance(None).expect("--sky has a sun");
        assert_eq!(sun_radiance(Some(1.0)), Some(one));
        let two = sun_radiance(Some(2.0)).expect("a sun");
        let off = (two - one * 2.0).map(f32::abs).max_component();
        assert!(
            off <= 1e-6 * one.max_component(),
            "{two:?} is not twice {one:?}"
        );
        assert_eq!(sun_radiance(Some(0.0)), None);
    }
}
