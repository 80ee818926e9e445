//! `fenestra.load`: a scene read as `fenestra render` reads its SCENE argument, its keywords
//! made into the session's typed request.

use crate::{error, session_error};
use anyhow::anyhow;
use fenestra_scene::sky::solar_position::Moment;
use fenestra_session::scene::axis_named;
use fenestra_session::{Lighting, LoadedScene, Placement, SceneRequest, SkyRequest, SunPlace};
use pyo3::prelude::*;
use std::path::PathBuf;

/// A loaded scene: rendered as many times as asked, each render from its own copy.
#[pyclass(frozen, module = "fenestra._native")]
pub struct Scene {
    pub loaded: LoadedScene,
}

#[pymethods]
impl Scene {
    /// What it was loaded from (`builtin:NAME` or a path).
    #[getter]
    fn source(&self) -> &str {
        &self.loaded.source
    }

    /// What the scene asks for that fenestra replaces or leaves out.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.loaded.warnings()
    }

    /// A glTF scene's cameras by name.
    #[getter]
    fn cameras(&self) -> Vec<String> {
        self.loaded.cameras.clone()
    }

    /// The scene's name.
    #[getter]
    fn name(&self) -> &str {
        &self.loaded.desc.name
    }

    /// The image size its file asks for: (width, height).
    #[getter]
    fn resolution(&self) -> (u32, u32) {
        (
            self.loaded.desc.defaults.width,
            self.loaded.desc.defaults.height,
        )
    }

    /// The samples per pixel its file asks for.
    #[getter]
    fn spp(&self) -> u32 {
        self.loaded.desc.defaults.spp
    }

    fn __repr__(&self) -> String {
        let (w, h) = self.resolution();
        format!(
            "<fenestra.Scene '{}' from {}: {} shapes, {} lights, {w}x{h}, {} spp>",
            self.loaded.desc.name,
            self.loaded.source,
            self.loaded.desc.shapes.len(),
            self.loaded.desc.lights.len(),
            self.loaded.desc.defaults.spp
        )
    }
}

/// Loads `source` (`builtin:NAME`, a pbrt-v4, glTF 2.0, OBJ or PLY file) as `fenestra
/// render` does with the same flags (the keywords are its scene flags).
#[pyfunction]
#[pyo3(signature = (source, *, strict=false, environment=None, sky=false, sky_turbidity=None,
    sky_albedo=None, sun=None, sun_time=None, location=None, sun_strength=None,
    environment_rotation=None,
    environment_strength=None, environment_up=None, camera=None))]
#[allow(clippy::too_many_arguments)]
pub fn load(
    py: Python<'_>,
    source: String,
    strict: bool,
    environment: Option<PathBuf>,
    sky: bool,
    sky_turbidity: Option<f32>,
    sky_albedo: Option<f32>,
    sun: Option<(f32, f32)>,
    sun_time: Option<String>,
    location: Option<(f32, f32)>,
    sun_strength: Option<f32>,
    environment_rotation: Option<f32>,
    environment_strength: Option<f32>,
    environment_up: Option<String>,
    camera: Option<String>,
) -> PyResult<Scene> {
    let needs_sky = [
        ("sky_turbidity", sky_turbidity.is_some()),
        ("sky_albedo", sky_albedo.is_some()),
        ("sun", sun.is_some()),
        ("sun_time", sun_time.is_some()),
        ("sun_strength", sun_strength.is_some()),
    ];
    if let Some((word, _)) = needs_sky.iter().find(|(_, given)| *given && !sky) {
        return Err(error(anyhow!(
            "{word} describes sky=True's sky; sky is not set"
        )));
    }
    if environment.is_some() && sky {
        return Err(error(anyhow!(
            "environment and sky both light the scene: give one"
        )));
    }
    let placing = [
        ("environment_rotation", environment_rotation.is_some()),
        ("environment_strength", environment_strength.is_some()),
        ("environment_up", environment_up.is_some()),
    ];
    if let Some((word, _)) = placing.iter().find(|(_, given)| *given) {
        if environment.is_none() && !sky {
            return Err(error(anyhow!(
                "{word} places environment or sky=True's sky; neither is given"
            )));
        }
    }
    let up = match environment_up.as_deref() {
        None => None,
        Some(axis) => Some(axis_named(axis).ok_or_else(|| {
            error(anyhow!(
                "environment_up: expected x, y, z, -x, -y or -z, got \"{axis}\""
            ))
        })?),
    };
    let placement = Placement {
        up,
        rotation_deg: environment_rotation.unwrap_or(0.0),
        strength: environment_strength.unwrap_or(1.0),
    };
    let lighting = match environment {
        Some(path) => Lighting::Environment { path, placement },
        None if sky => Lighting::Sky {
            sky: sky_request(
                sky_turbidity,
                sky_albedo,
                sun,
                sun_time,
                location,
                sun_strength,
            )?,
            placement,
        },
        None => Lighting::Own,
    };
    let request = SceneRequest {
        source,
        strict,
        camera,
        lighting,
    };
    let loaded = py
        .detach(|| fenestra_session::load(&request))
        .map_err(session_error)?;
    Ok(Scene { loaded })
}

/// sky=True's sky and sun from their keywords.
fn sky_request(
    turbidity: Option<f32>,
    albedo: Option<f32>,
    sun: Option<(f32, f32)>,
    sun_time: Option<String>,
    location: Option<(f32, f32)>,
    sun_strength: Option<f32>,
) -> PyResult<SkyRequest> {
    let defaults = SkyRequest::default();
    if sun_time.is_some() != location.is_some() {
        return Err(error(anyhow!(
            "sun_time and location go together: the sun at that moment seen from there"
        )));
    }
    let sun = match (sun, sun_time, location) {
        (Some(_), Some(_), _) => {
            return Err(error(anyhow!(
                "sun and sun_time both place the sun: give one"
            )))
        }
        (Some((elevation_deg, azimuth_deg)), ..) => SunPlace::Angles {
            elevation_deg,
            azimuth_deg,
        },
        (None, Some(time), Some((latitude, longitude))) => SunPlace::At {
            moment: Moment::parse(&time).map_err(|e| error(anyhow!("sun_time: {e}")))?,
            latitude,
            longitude,
        },
        _ => defaults.sun,
    };
    Ok(SkyRequest {
        turbidity: turbidity.unwrap_or(defaults.turbidity),
        albedo: albedo.unwrap_or(defaults.albedo),
        sun,
        sun_strength: sun_strength.unwrap_or(defaults.sun_strength),
    })
}
