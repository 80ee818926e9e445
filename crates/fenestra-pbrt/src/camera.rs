//! The camera and its pixel filter: the Camera and PixelFilter directives, and the camera
//! the scene is seen through once the world begins.

use crate::builder::{Builder, CameraSpec};
use crate::parser::Directive;
use crate::{PbrtError, Topic};
use fenestra_core::Vec2;
use fenestra_scene::filter::{FilterShape, PixelFilter};
use fenestra_scene::{Camera, FieldOfView};
use glam::DVec3;

impl Builder {
    pub(crate) fn camera(&mut self, d: &Directive) {
        let p = &d.params;
        if d.str(0) != "perspective" {
            self.warn(
                Topic::Camera,
                format!("Camera \"{}\" (rendered as perspective)", d.str(0)),
                &d.loc,
            );
            p.use_all();
        }
        let fov = p.float("fov", 90.0).unwrap_or(90.0);
        let screen_window = p
            .floats("screenwindow")
            .ok()
            .flatten()
            .and_then(|v| <[f32; 4]>::try_from(v.as_slice()).ok());
        if p.float("lensradius", 0.0).unwrap_or(0.0) > 0.0 {
            self.warn(
                Topic::Camera,
                "Camera \"lensradius\" > 0 (depth of field; rendered as a pinhole)",
                &d.loc,
            );
        }
        p.float("focaldistance", 1e6).ok();
        let open = p.float("shutteropen", 0.0).unwrap_or(0.0);
        let close = p.float("shutterclose", 1.0).unwrap_or(1.0);
        if close >= open {
            self.shutter = (close - open, Some(d.loc.clone()));
        } else {
            self.warn(
                Topic::Camera,
                format!(
                    "shutterclose {close} before shutteropen {open} (the exposure is taken as 1 s)"
                ),
                &d.loc,
            );
        }
        self.named_coords
            .insert("camera".into(), self.gs.ctm.inverse());
        self.camera = Some(CameraSpec {
            camera_from_world: self.gs.ctm,
            fov,
            screen_window,
            loc: d.loc.clone(),
        });
    }

    /// pbrt-v4's PixelFilter with its parameters and defaults.
    pub(crate) fn pixel_filter(&mut self, d: &Directive) -> Result<PixelFilter, PbrtError> {
        let p = &d.params;
        let (shape, radius) = match d.str(0) {
            "box" => (FilterShape::Box, 0.5),
            "triangle" => (FilterShape::Triangle, 2.0),
            "gaussian" => (
                FilterShape::Gaussian {
                    sigma: p.float("sigma", 0.5)?,
                },
                1.5,
            ),
            "mitchell" => (
                FilterShape::Mitchell {
                    b: p.float("B", 1.0 / 3.0)?,
                    c: p.float("C", 1.0 / 3.0)?,
                },
                2.0,
            ),
            "sinc" => (
                FilterShape::Sinc {
                    tau: p.float("tau", 3.0)?,
                },
                4.0,
            ),
            other => {
                return Err(PbrtError::at(
                    &d.loc,
                    format!(
                    "unknown PixelFilter \"{other}\" (box, triangle, gaussian, mitchell or sinc)"
                ),
                ))
            }
        };
        let radius = Vec2::new(p.float("xradius", radius)?, p.float("yradius", radius)?);
        let width_ok = match shape {
            FilterShape::Gaussian { sigma } => sigma > 0.0 && sigma.is_finite(),
            FilterShape::Sinc { tau } => tau > 0.0 && tau.is_finite(),
            _ => true,
        };
        let radius_ok = radius.min_element() > 0.0 && radius.max_element() <= 64.0;
        if !(radius_ok && width_ok) {
            return Err(PbrtError::at(
                &d.loc,
                "PixelFilter radii must be in (0, 64] pixels and sigma and tau positive",
            ));
        }
        if matches!(
            shape,
            FilterShape::Mitchell { .. } | FilterShape::Sinc { .. }
        ) {
            self.warn(
                Topic::Camera,
                format!(
                    "PixelFilter \"{}\" negative lobes (its positive part is used)",
                    d.str(0)
                ),
                &d.loc,
            );
        }
        Ok(PixelFilter::new(shape, radius))
    }
}

impl CameraSpec {
    /// The camera the spec describes.
    pub(crate) fn build(&self) -> Result<Camera, PbrtError> {
        let c = self;
        let m = c.camera_from_world.inverse();
        let v = |x: DVec3| x.as_vec3();
        if !m.is_finite() {
            return Err(PbrtError::at(&c.loc, "the camera transform is singular"));
        }
        Camera::from_basis(
            v(m.transform_point3(DVec3::ZERO)),
            v(m.transform_vector3(DVec3::Z)),
            v(m.transform_vector3(DVec3::X)),
            v(m.transform_vector3(DVec3::Y)),
            FieldOfView::ShorterAxis(c.fov),
            c.screen_window,
        )
        .map_err(|e| PbrtError::at(&c.loc, e.to_string()))
    }
}
