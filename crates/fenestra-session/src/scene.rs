//! A scene asked for (`builtin:NAME`, a pbrt-v4 file, a glTF 2.0 scene, or an OBJ/PLY mesh
//! staged for viewing) with the light it is shown under, and the scene loaded from it.

use crate::error::{literal, Error, Result, Setting};
use anyhow::{anyhow, Context};
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

/// A scene to load.
#[derive(Clone, Debug)]
pub struct SceneRequest {
    /// `builtin:NAME`, or the path of a pbrt-v4, glTF 2.0, OBJ or PLY file.
    pub source: String,
    /// Refuse files that use anything fenestra does not support (instead of warning).
    pub strict: bool,
    /// A glTF scene's camera, by name or index (default: its first, or one framing the scene).
    pub camera: Option<String>,
    /// What lights it besides its own lights.
    pub lighting: Lighting,
}

impl SceneRequest {
    /// `source` as its file describes it.
    pub fn new(source: impl Into<String>) -> Self {
        SceneRequest {
            source: source.into(),
            strict: false,
            camera: None,
            lighting: Lighting::Own,
        }
    }
}

/// What lights a scene from afar.
#[derive(Clone, Debug, Default)]
pub enum Lighting {
    /// Its own environment, if it has one.
    #[default]
    Own,
    /// An environment map instead of its own environment (its other lights stay): a 2:1
    /// latitude-longitude image (EXR, HDR or PFM; row 0 the zenith).
    Environment { path: PathBuf, placement: Placement },
    /// A physical clear sky and its sun (Hosek-Wilkie 2012 sky, SPECTRL2 sun disk of 0.53
    /// degrees) instead of its own environment (its other lights stay).
    Sky {
        sky: SkyRequest,
        placement: Placement,
    },
}

/// How an environment or sky sits around the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The scene's up axis (default: the world axis nearest the camera's up).
    pub up: Option<Vec3>,
    /// A turn about the up axis, degrees counter-clockwise seen from above.
    pub rotation_deg: f32,
    /// A factor on its radiance (and the sun's).
    pub strength: f32,
}

impl Default for Placement {
    fn default() -> Self {
        Placement {
            up: None,
            rotation_deg: 0.0,
            strength: 1.0,
        }
    }
}

/// A clear sky and its sun.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyRequest {
    /// Atmospheric turbidity: 1 (arctic clear) to 10 (hazy).
    pub turbidity: f32,
    /// Ground albedo (in the sky model, and the ground below the horizon).
    pub albedo: f32,
    /// Where the sun stands.
    pub sun: SunPlace,
    /// A factor on the sun's disk (on top of the placement's strength); 0 takes it away.
    pub sun_strength: f32,
}

impl Default for SkyRequest {
    /// A clear temperate day, the sun at 45 degrees in the south.
    fn default() -> Self {
        SkyRequest {
            turbidity: 3.0,
            albedo: 0.3,
            sun: SunPlace::default(),
            sun_strength: 1.0,
        }
    }
}

/// Where a sky's sun stands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SunPlace {
    /// Elevation above the horizon and azimuth clockwise from north (the environment's
    /// phi = 0 direction, turned by the placement), degrees.
    Angles {
        elevation_deg: f32,
        azimuth_deg: f32,
    },
    /// Where it stands at `moment` seen from latitude and longitude (degrees, north and east
    /// positive).
    At {
        moment: Moment,
        latitude: f32,
        longitude: f32,
    },
}

impl Default for SunPlace {
    fn default() -> Self {
        SunPlace::Angles {
            elevation_deg: 45.0,
            azimuth_deg: 180.0,
        }
    }
}

/// A loaded scene with what it could not represent and the files it read.
#[derive(Clone)]
pub struct LoadedScene {
    /// What it was loaded from (`builtin:NAME` or a path).
    pub source: String,
    pub desc: SceneDesc,
    /// What a pbrt-v4 file asks for that fenestra replaces by something else.
    pub substitutions: Vec<pbrt::Warning>,
    /// What a pbrt-v4 file asks for that fenestra renders in its own documented way.
    pub notes: Vec<pbrt::Warning>,
    /// Other warnings: mesh files, a scene without light.
    pub other: Vec<String>,
    /// Seconds the loading took.
    pub seconds: f64,
    /// Every file read (scene, includes, meshes, images): outputs must not replace them.
    pub files: Vec<PathBuf>,
    /// A glTF file's cameras by name, in index order (empty for other scenes).
    pub cameras: Vec<String>,
    /// The sky it is lit by, with the strength it was given.
    pub sky: Option<(Sky, f32)>,
}

impl LoadedScene {
    /// Every warning as a line of text: substitutions, then the others.
    pub fn warnings(&self) -> Vec<String> {
        let subs = self.substitutions.iter().map(ToString::to_string);
        subs.chain(self.other.iter().cloned()).collect()
    }
}

/// Loads the scene `request` asks for.
pub fn load(request: &SceneRequest) -> Result<LoadedScene> {
    let start = Instant::now();
    let arg = request.source.as_str();
    let format = mesh::format_of(Path::new(arg));
    if request.camera.is_some() && !matches!(format.as_deref(), Some("gltf" | "glb")) {
        return Err(Error::setting(
            Setting::Camera,
            format!(
                "picks a glTF scene's camera; {} is not a .gltf or .glb file",
                literal(arg)
            ),
        ));
    }
    let (mut substitutions, mut notes, mut cameras) = (Vec::new(), Vec::new(), Vec::new());
    let (desc, mut warnings, files) = if let Some(name) = arg.strip_prefix("builtin:") {
        (
            builtin::load(name).map_err(anyhow::Error::from)?,
            Vec::new(),
            Vec::new(),
        )
    } else {
        let path = Path::new(arg);
        match format.as_deref() {
            Some("pbrt") => {
                let l = pbrt::load(path, request.strict).map_err(anyhow::Error::from)?;
                (substitutions, notes) = (l.warnings, l.notes);
                (l.desc, Vec::new(), l.files)
            }
            Some("gltf" | "glb") => {
                let l = fenestra_gltf::load(path, request.camera.as_deref())
                    .map_err(anyhow::Error::from)?;
                if request.strict && !l.warnings.is_empty() {
                    return Err(anyhow!("{arg}: refused (strict): {}", l.warnings.join("; ")).into());
                }
                let warnings = l.warnings.iter().map(|w| format!("{arg}: {w}")).collect();
                cameras = l.cameras;
                (l.desc, warnings, l.files)
            }
            Some("obj" | "ply") => {
                let m = mesh::viewer_scene(path).map_err(anyhow::Error::from)?;
                let textures = m
                    .desc
                    .materials
                    .iter()
                    .filter_map(|m| m.texture().map(|t| t.path.clone()));
                let files = m.files.into_iter().chain(textures).collect();
                (m.desc, m.warnings, files)
            }
            _ => return Err(anyhow!(
                "{arg}: unknown scene type (expected a .pbrt or .pbrt.gz file, a .gltf or .glb scene, an .obj or .ply mesh, or builtin:NAME; `fenestra list` shows the built-in scenes)"
            ).into()),
        }
    };
    let mut sky = None;
    let (desc, files) = match &request.lighting {
        Lighting::Own => (desc, files),
        Lighting::Environment { path, placement } => (
            with_environment(desc, path, placement)?,
            [files, vec![path.clone()]].concat(),
        ),
        Lighting::Sky {
            sky: request,
            placement,
        } => {
            let (desc, s) = with_sky(desc, request, placement)?;
            sky = Some((s, placement.strength));
            (desc, files)
        }
    };
    if desc.lights.is_empty() && desc.shapes.iter().all(|s| s.emission.is_none()) {
        warnings.push(format!(
            "{arg}: the scene has no light (no light source, no emissive shape): it renders black"
        ));
    }
    Ok(LoadedScene {
        source: request.source.clone(),
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

/// `desc` lit by the environment map at `path` placed as `placement` says.
fn with_environment(desc: SceneDesc, path: &Path, placement: &Placement) -> Result<SceneDesc> {
    let image = Image::read(path)
        .with_context(|| path.display().to_string())
        .map_err(|e| Error::setting(Setting::Environment, literal(&format!("{e:#}"))))?;
    let map = EnvironmentMap {
        image: Arc::new(image),
        up: placement.up.unwrap_or_else(|| desc.camera_up_axis()),
        rotation_deg: placement.rotation_deg,
        strength: placement.strength,
    };
    if let Some(problem) = map.validate() {
        return Err(Error::setting(
            Setting::Environment,
            literal(&format!("{}: {problem}", path.display())),
        ));
    }
    Ok(desc.with_environment(&map))
}

/// `desc` lit by the clear sky and sun `request` describes, placed as `placement` says, and
/// that sky.
fn with_sky(
    desc: SceneDesc,
    request: &SkyRequest,
    placement: &Placement,
) -> Result<(SceneDesc, Sky)> {
    let (elevation_deg, azimuth_deg) = match request.sun {
        SunPlace::Angles {
            elevation_deg,
            azimuth_deg,
        } => {
            if !(elevation_deg.is_finite() && azimuth_deg.is_finite()) {
                return Err(Error::setting(
                    Setting::Sun,
                    format!("needs finite angles in degrees, got {elevation_deg},{azimuth_deg}"),
                ));
            }
            (elevation_deg, azimuth_deg)
        }
        SunPlace::At {
            moment,
            latitude,
            longitude,
        } => {
            if !(latitude.abs() <= 90.0 && longitude.abs() <= 180.0) {
                return Err(Error::setting(
                    Setting::Location,
                    format!("must be a latitude in -90..90 and a longitude in -180..180 degrees, got {latitude},{longitude}"),
                ));
            }
            let (el, az) = sun_position(&moment, latitude as f64, longitude as f64);
            if el < 0.0 {
                return Err(Error::setting(
                    Setting::SunTime,
                    format!("at {latitude},{longitude}: the sun is {:.1} degrees below the horizon (the sky model covers a sun above it)", -el),
                ));
            }
            (el as f32, az as f32)
        }
    };
    let sky = Sky {
        turbidity: request.turbidity,
        albedo: request.albedo,
        elevation_deg,
        azimuth_deg,
    };
    let up = placement.up.unwrap_or_else(|| desc.camera_up_axis());
    let mut desc = desc
        .with_sky(&sky, up, placement.rotation_deg, placement.strength)
        .map_err(|problem| Error::setting(Setting::Sky, format!(": {problem}")))?;
    let k = request.sun_strength;
    if !(k.is_finite() && k >= 0.0) {
        return Err(Error::setting(
            Setting::SunStrength,
            format!("must be 0 or more, got {k}"),
        ));
    }
    desc.lights.retain_mut(|light| match light {
        LightDesc::Environment(EnvironmentDesc::Sun { radiance, .. }) => {
            *radiance *= k;
            k > 0.0
        }
        _ => true,
    });
    Ok((desc, sky))
}

/// A world axis by name: x, y, z, -x, -y or -z (+x too).
pub fn axis_named(name: &str) -> Option<Vec3> {
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

    /// The sun's radiance in `builtin:box-hole` under a sky with sun strength `k`.
    fn sun_radiance(k: f32) -> Option<fenestra_core::Rgb> {
        let request = SceneRequest {
            lighting: Lighting::Sky {
                sky: SkyRequest {
                    sun_strength: k,
                    ..SkyRequest::default()
                },
                placement: Placement::default(),
            },
            ..SceneRequest::new("builtin:box-hole")
        };
        let loaded = load(&request).expect("the scene under a sky");
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
        let one = sun_radiance(1.0).expect("a sky has a sun");
        let two = sun_radiance(2.0).expect("a sun");
        let off = (two - one * 2.0).map(f32::abs).max_component();
        assert!(
            off <= 1e-6 * one.max_component(),
            "{two:?} is not twice {one:?}"
        );
        assert_eq!(sun_radiance(0.0), None);
        let e = load(&SceneRequest {
            lighting: Lighting::Sky {
                sky: SkyRequest {
                    sun_strength: -1.0,
                    ..SkyRequest::default()
                },
                placement: Placement::default(),
            },
            ..SceneRequest::new("builtin:box-hole")
        })
        .err()
        .expect("a negative sun");
        assert_eq!(
            e.worded(crate::Style::Flag),
            "--sun-strength must be 0 or more, got -1"
        );
        assert_eq!(e.to_string(), "sun_strength must be 0 or more, got -1");
    }
}
