//! pbrt-v4 light sources: point, spot, distant, infinite (constant, or an image: pbrt-v4's
//! square equal-area octahedral maps are resampled to fenestra's latitude-longitude layout,
//! and 2:1 images are read as latitude-longitude directly), and diffuse area lights.
//! "power" and "illuminance" rescale the spectrum as pbrt-v4 does (`scaled`), including
//! pbrt-v4's own conventions: an image map's illuminance is counted with half the solid angle
//! of its pixels, and an emissive mesh's power is each triangle's.

use crate::builder::{AreaSpec, Builder};
use crate::equal_area::{equal_area_to_latlong, square_to_sphere};
use crate::params::ParamList;
use crate::parser::Directive;
use crate::spectra;
use crate::{Loc, PbrtError, Topic};
use fenestra_core::image::read_exr_channel_names;
use fenestra_core::image::Image;
use fenestra_core::{Rgb, Vec3, PI};
use fenestra_scene::light::{EnvironmentDesc, LightDesc};
use glam::DMat3;
use std::path::Path;
use std::sync::Arc;

impl Builder {
    pub(super) fn light(&mut self, d: &Directive, dir: &Path) -> Result<(), PbrtError> {
        let p = &d.params;
        let ctm = self.gs.ctm;
        let point = |v: Vec3| ctm.transform_point3(v.as_dvec3()).as_vec3();
        let vector = |v: Vec3| ctm.transform_vector3(v.as_dvec3()).as_vec3();
        let scale = p.float("scale", 1.0)?;
        if !ctm.is_finite() {
            return Err(PbrtError::at(&d.loc, "the current transform is not finite"));
        }
        let light = match d.str(0) {
            "point" => {
                let mut i = spectrum(p, "I", &d.loc)? * scale;
                if let Some(power) = p.opt_float("power")? {
                    i = scaled(i, power / (4.0 * PI), &d.loc)?;
                }
                LightDesc::Point {
                    position: point(p.point3("from", Vec3::ZERO)?),
                    intensity: i,
                }
            }
            "spot" => {
                let cone = p.float("coneangle", 30.0)?;
                // pbrt-v4's name; fenestra's exports before 2026-11 wrote "conedelta".
                let delta = match p.opt_float("conedelta")? {
                    Some(delta) => {
                        self.warn(
                            Topic::Lights,
                            "spot \"conedelta\" (pbrt-v4 names it \"conedeltaangle\"; read as that)",
                            &d.loc,
                        );
                        delta
                    }
                    None => p.float("conedeltaangle", 5.0)?,
                };
                let mut i = spectrum(p, "I", &d.loc)? * scale;
                if let Some(power) = p.opt_float("power")? {
                    let (cos_total, cos_start) =
                        (cone.to_radians().cos(), (cone - delta).to_radians().cos());
                    let k = 2.0 * PI * ((1.0 - cos_start) + (cos_start - cos_total) / 2.0);
                    i = scaled(i, power / k, &d.loc)?;
                }
                let from = p.point3("from", Vec3::ZERO)?;
                let to = p.point3("to", Vec3::Z)?;
                LightDesc::Spot {
                    position: point(from),
                    direction: vector(to - from).normalize_or_zero(),
                    intensity: i,
                    cone_angle: cone,
                    falloff_start: (cone - delta).max(0.0),
                }
            }
            "distant" => {
                let mut l = spectrum(p, "L", &d.loc)? * scale;
                if let Some(e) = p.opt_float("illuminance")? {
                    l = scaled(l, e, &d.loc)?;
                }
                let from = p.point3("from", Vec3::ZERO)?;
                let to = p.point3("to", Vec3::Z)?;
                LightDesc::Distant {
                    direction: vector(to - from).normalize_or_zero(),
                    irradiance: l,
                }
            }
            "infinite" => self.infinite(d, dir, scale)?,
            other => {
                self.warn(
                    Topic::Lights,
                    format!("LightSource \"{other}\" (skipped)"),
                    &d.loc,
                );
                p.use_all();
                return Ok(());
            }
        };
        if self.object.is_some() {
            self.warn(
                Topic::Lights,
                "light sources inside object definitions (skipped)",
                &d.loc,
            );
            return Ok(());
        }
        if let Some(what) = light.problem() {
            return Err(PbrtError::at(&d.loc, what));
        }
        self.lights.push(light);
        Ok(())
    }

    fn infinite(&mut self, d: &Directive, dir: &Path, scale: f32) -> Result<LightDesc, PbrtError> {
        let p = &d.params;
        let ctm = self.gs.ctm;
        if let Some(corners) = p.point3s("portal")? {
            if corners.len() != 4 {
                return Err(PbrtError::at(
                    &d.loc,
                    format!("\"point3 portal\" needs 4 points, found {}", corners.len()),
                ));
            }
            let c: [Vec3; 4] =
                std::array::from_fn(|i| ctm.transform_point3(corners[i].as_dvec3()).as_vec3());
            self.portals.push(c);
        }
        let illuminance = p.opt_float("illuminance")?;
        let filename = p.string("filename")?;
        if filename.is_some() && p.has("L") {
            return Err(PbrtError::at(
                &d.loc,
                "infinite light: give either \"L\" or \"filename\", not both",
            ));
        }
        let Some(file) = filename else {
            let mut l = spectrum(p, "L", &d.loc)? * scale;
            if let Some(e) = illuminance {
                // A constant sky of luminance Y gives illuminance pi Y on a horizontal plane.
                l = scaled(l, e / PI, &d.loc)?;
            }
            return Ok(LightDesc::Environment(EnvironmentDesc::Constant(l)));
        };
        let path = dir.join(&file);
        let img = self.image(&path, &d.loc)?;
        // pbrt-v4's reference illuminance of the map (below), on the pixels it was given.
        let reference = if img.width == img.height {
            let order = if path
                .extension()
                .is_some_and(|x| x.eq_ignore_ascii_case("exr"))
            {
                read_exr_channel_names(&path).map_err(|e| PbrtError::at(&d.loc, e.to_string()))?
            } else {
                vec!["R".into(), "G".into(), "B".into()]
            };
            equal_area_reference_illuminance(&img, &order)
        } else {
            0.5 * upper_illuminance(&img)
        };
        let latlong = if img.width == img.height {
            self.note(
                Topic::Lights,
                "equal-area environment map resampled to latitude-longitude (bilinear; detail finer than a texel softens)",
                &d.loc,
            );
            Arc::new(equal_area_to_latlong(&img))
        } else if img.width == 2 * img.height {
            img
        } else {
            return Err(PbrtError::at(
                &d.loc,
                format!(
                    "{}: environment images must be square (pbrt-v4 equal-area) or 2:1 (latitude-longitude), found {}x{}",
                    path.display(),
                    img.width,
                    img.height
                ),
            ));
        };
        let linear = DMat3::from_mat4(ctm);
        let to_world = orthonormal(&linear).ok_or_else(|| {
            PbrtError::at(
                &d.loc,
                "the transform of an image infinite light must be a rotation",
            )
        })?;
        let mut s = scale;
        if let Some(e) = illuminance {
            if !(reference > 0.0) {
                return Err(PbrtError::at(
                    &d.loc,
                    "\"illuminance\" given for an image that is black above the horizon",
                ));
            }
            s *= e / reference;
        }
        Ok(LightDesc::Environment(EnvironmentDesc::Image {
            image: latlong,
            scale: Rgb::splat(s),
            to_world: to_world.as_mat3(),
        }))
    }

    pub(super) fn area_light(&mut self, d: &Directive) -> Result<(), PbrtError> {
        let p = &d.params;
        if d.str(0) != "diffuse" {
            self.warn(
                Topic::Lights,
                format!("AreaLightSource \"{}\" (skipped)", d.str(0)),
                &d.loc,
            );
            p.use_all();
            return Ok(());
        }
        if p.has("filename") {
            self.warn(
                Topic::Lights,
                "image area lights (\"filename\"; L is used)",
                &d.loc,
            );
            p.string("filename")?;
        }
        let radiance = spectrum(p, "L", &d.loc)? * p.float("scale", 1.0)?;
        self.gs.area = Some(AreaSpec {
            radiance,
            two_sided: p.bool("twosided", false)?,
            power: p.opt_float("power")?,
        });
        Ok(())
    }
}

/// A light's spectrum parameter as RGB; pbrt-v4's default is the colour space's white.
fn spectrum(p: &ParamList, name: &str, _loc: &Loc) -> Result<Rgb, PbrtError> {
    match p.spectrum(name)? {
        Some((s, l)) => spectra::illuminant_to_rgb(&s).map_err(|e| PbrtError::at(&l, e)),
        None => Ok(Rgb::ONE),
    }
}

/// The emission `c` times `k`, the factor "power" or "illuminance" asks for, as pbrt-v4 applies
/// it: to the spectrum as given when it is RGB (pbrt-v4 normalises an RGB illuminant by its
/// white, so an RGB light keeps its own luminance) and to a luminance-1 spectrum otherwise
/// (blackbody and named or sampled spectra come from `spectra` with luminance 1, as pbrt-v4
/// divides them by their photometric value); the light's "scale" stays.
fn scaled(c: Rgb, k: f32, loc: &Loc) -> Result<Rgb, PbrtError> {
    if c.luminance() > 0.0 && k.is_finite() && k >= 0.0 {
        Ok(c * k)
    } else {
        Err(PbrtError::at(
            loc,
            "power or illuminance needs a spectrum of positive luminance",
        ))
    }
}

fn orthonormal(m: &DMat3) -> Option<DMat3> {
    let s = m.x_axis.length();
    let ok = [m.x_axis, m.y_axis, m.z_axis]
        .iter()
        .all(|c| (c.length() - s).abs() < 1e-4 * s)
        && m.x_axis.dot(m.y_axis).abs() < 1e-4 * s * s
        && m.x_axis.dot(m.z_axis).abs() < 1e-4 * s * s
        && s > 0.0;
    ok.then(|| *m * (1.0 / s))
}

/// Illuminance (luminance-weighted) a latitude-longitude map gives a surface facing +z,
/// exact for the piecewise-constant map: a texel row between theta0 and theta1 contributes
/// dphi * (sin^2 theta1 - sin^2 theta0) / 2 per unit radiance.
/// The illuminance pbrt-v4 normalises an equal-area map's "illuminance" by: the sum over the
/// pixels whose centre lies above the horizon of luminance times cos theta, each weighted
/// 2pi / N, half the 4pi / N a pixel covers, so a map given illuminance E shines with about
/// 2E. Its luminance weighs the file's first three channels in the file's `order` by the red,
/// green and blue weights: an OpenEXR file lists "B", "G", "R" (after "A" when it has one,
/// whose value is taken as 1), so blue is weighed as red (measured against pbrt-v4: the
/// light-infinite-image scene, 3.7% apart otherwise). A latitude-longitude map, which
/// pbrt-v4 does not read, gets half its true illuminance, the same convention.
fn equal_area_reference_illuminance(img: &Image, order: &[String]) -> f32 {
    const WEIGHTS: [f32; 3] = [0.2126, 0.7152, 0.0722];
    let (mut rgb, mut alpha) = (Rgb::ZERO, 0.0);
    for (name, w) in order.iter().zip(WEIGHTS) {
        match name.as_str() {
            "R" => rgb.r += w,
            "G" => rgb.g += w,
            "B" => rgb.b += w,
            _ => alpha += w,
        }
    }
    let n = img.width;
    let mut e = 0.0f64;
    for y in 0..n {
        for x in 0..n {
            let w = square_to_sphere((x as f64 + 0.5) / n as f64, (y as f64 + 0.5) / n as f64);
            if w.z > 0.0 {
                let c = img.get(x, y);
                let lum = c.r * rgb.r + c.g * rgb.g + c.b * rgb.b + alpha;
                e += f64::from(lum) * w.z;
            }
        }
    }
    (e * 2.0 * std::f64::consts::PI / (n * n) as f64) as f32
}

fn upper_illuminance(img: &Image) -> f32 {
    let (w, h) = (img.width, img.height);
    let dphi = 2.0 * std::f64::consts::PI / w as f64;
    let mut e = 0.0f64;
    for row in 0..h {
        let t0 = std::f64::consts::PI * row as f64 / h as f64;
        let t1 =
            (std::f64::consts::PI * (row + 1) as f64 / h as f64).min(std::f64::consts::FRAC_PI_2);
        if t1 <= t0 {
            break;
        }
        let weight = dphi * (t1.sin().powi(2) - t0.sin().powi(2)) / 2.0;
        let sum: f64 = (0..w).map(|col| img.get(col, row).luminance() as f64).sum();
        e += sum * weight;
    }
    e as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_map_illuminance_is_pi_times_radiance() {
        let mut img = Image::new(64, 32);
        for y in 0..32 {
            for x in 0..64 {
                img.set(x, y, Rgb::splat(2.0));
            }
        }
        assert!((upper_illuminance(&img) / (2.0 * PI) - 1.0).abs() < 1e-5);
        let sq = {
            let mut s = Image::new(16, 16);
            for y in 0..16 {
                for x in 0..16 {
                    s.set(x, y, Rgb::splat(3.0));
                }
            }
            s
        };
        let ll = equal_area_to_latlong(&sq);
        assert_eq!((ll.width, ll.height), (32, 16));
        assert!((ll.mean().r - 3.0).abs() < 1e-5);
    }
}
