//! The directives that set up the render rather than the scene: Film, Sampler, Integrator
//! (its options read as fenestra's), PixelFilter, and those fenestra takes as sRGB, vacuum or
//! not at all.

use crate::builder::{positive, Builder};
use crate::parser::Directive;
use crate::{PbrtError, Topic};

/// The camera sensors whose spectral curves pbrt-v4 carries (its `sensor` names).
const SENSORS: [&str; 17] = [
    "canon_eos_100d",
    "canon_eos_1dx_mkii",
    "canon_eos_200d",
    "canon_eos_200d_mkii",
    "canon_eos_5d",
    "canon_eos_5d_mkii",
    "canon_eos_5d_mkiii",
    "canon_eos_5d_mkiv",
    "canon_eos_5ds",
    "canon_eos_m",
    "hasselblad_l1d_20c",
    "nikon_d810",
    "nikon_d850",
    "sony_ilce_6400",
    "sony_ilce_7m3",
    "sony_ilce_7rm3",
    "sony_ilce_9",
];

impl Builder {
    /// A directive that sets up the render.
    pub(crate) fn rendering(&mut self, d: &Directive) -> Result<(), PbrtError> {
        match d.name {
            "Film" => {
                if !matches!(d.str(0), "rgb" | "gbuffer") {
                    self.warn(
                        Topic::Camera,
                        format!("Film \"{}\" (rendered as rgb)", d.str(0)),
                        &d.loc,
                    );
                }
                let p = &d.params;
                let iso = p.float("iso", 100.0)?;
                if !(iso.is_finite() && iso > 0.0) {
                    return Err(PbrtError::at(
                        &d.loc,
                        format!("iso must be positive, found {iso}"),
                    ));
                }
                self.iso = (iso, Some(d.loc.clone()));
                let sensor = p.string("sensor")?.unwrap_or_else(|| "cie1931".into());
                let balance = p.float("whitebalance", 0.0)?;
                if !(balance.is_finite() && balance >= 0.0) {
                    return Err(PbrtError::at(
                        &d.loc,
                        format!("whitebalance must be a colour temperature in kelvin (0: none), found {balance}"),
                    ));
                }
                if sensor != "cie1931" {
                    if !SENSORS.contains(&sensor.as_str()) {
                        return Err(PbrtError::at(
                            &d.loc,
                            format!(
                                "unknown sensor \"{sensor}\" (pbrt-v4 knows cie1931, {})",
                                SENSORS.join(", ")
                            ),
                        ));
                    }
                    // pbrt-v4 balances a camera's sensor for 6500 K unless told otherwise.
                    let balance = if balance > 0.0 { balance } else { 6500.0 };
                    self.white_balance = Some(balance);
                    self.warn(
                        Topic::Camera,
                        format!("sensor \"{sensor}\" (rendered with the CIE 1931 observer, white-balanced for {balance} K as pbrt-v4 balances the sensor; the camera's own colour response needs a spectral renderer: up to 8% per channel, docs/scenes.md)"),
                        &d.loc,
                    );
                } else if balance > 0.0 {
                    self.white_balance = Some(balance);
                }
                self.defaults.width = positive(p.int("xresolution", 1280)?, "xresolution", &d.loc)?;
                self.defaults.height = positive(p.int("yresolution", 720)?, "yresolution", &d.loc)?;
                // The output file is named on the command line.
                p.string("filename")?;
            }
            "Sampler" => {
                // Any pbrt sampler maps to fenestra's Owen-scrambled Sobol sequence.
                self.defaults.spp =
                    positive(d.params.int("pixelsamples", 16)?, "pixelsamples", &d.loc)?;
                d.params.int("seed", 0)?;
            }
            "Integrator" => {
                if !matches!(d.str(0), "path" | "volpath") {
                    self.warn(
                        Topic::Rendering,
                        format!(
                            "Integrator \"{}\" (rendered with af_hf, a path tracer)",
                            d.str(0)
                        ),
                        &d.loc,
                    );
                    d.params.use_all();
                }
                let depth = d.params.int("maxdepth", 5)?;
                // pbrt counts bounces; fenestra counts segments from the camera (2 = direct).
                self.defaults.max_depth = positive(depth + 1, "maxdepth", &d.loc)?;
                self.integrator_options(d)?;
            }
            "PixelFilter" => self.filter = Some(self.pixel_filter(d)?),
            // The acceleration structure does not change the picture.
            "Accelerator" => d.params.use_all(),
            "ColorSpace" if d.str(0) == "srgb" => {}
            "ColorSpace" | "Option" | "Attribute" | "MakeNamedMedium" | "MediumInterface" => {
                let effect = match d.name {
                    "ColorSpace" => "colours are taken as sRGB",
                    "MakeNamedMedium" | "MediumInterface" => {
                        "participating media: light passes as through vacuum"
                    }
                    _ => "ignored",
                };
                self.warn(
                    Topic::Rendering,
                    format!("{} \"{}\" ({effect})", d.name, d.str(0)),
                    &d.loc,
                );
                d.params.use_all();
            }
            other => unreachable!("directive {other} is dispatched here by its name"),
        }
        Ok(())
    }

    /// The options of a path tracing Integrator directive that fenestra's integrators read:
    /// its light sampler becomes `light.selection` (pbrt-v4's bvh, power and uniform have
    /// fenestra namesakes; exhaustive, which weighs every light by its bounds' importance,
    /// is taken as bvh, whose cuts approximate it).
    fn integrator_options(&mut self, d: &Directive) -> Result<(), PbrtError> {
        if let Some(sampler) = d.params.string("lightsampler")? {
            let selection = match sampler.as_str() {
                "bvh" | "power" | "uniform" => sampler.clone(),
                "exhaustive" => {
                    self.note(
                        Topic::Rendering,
                        "lightsampler \"exhaustive\" (taken as bvh)",
                        &d.loc,
                    );
                    "bvh".to_string()
                }
                other => {
                    return Err(PbrtError::at(
                        &d.loc,
                        format!(
                            "unknown lightsampler \"{other}\" (pbrt-v4 has bvh, exhaustive, power and uniform)"
                        ),
                    ))
                }
            };
            self.defaults
                .options
                .push(("light.selection".into(), selection));
        }
        if d.params.bool("regularize", false)? {
            self.warn(
                Topic::Rendering,
                "regularize (fenestra does not regularize BSDFs: caustics stay sharp and noisy)",
                &d.loc,
            );
        }
        Ok(())
    }
}
