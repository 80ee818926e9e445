//! `--denoise` on `render` and `merge`: the option and what it adds to a render's outputs.

use anyhow::Result;
use clap::Args;
use fenestra_core::image::Image;
use fenestra_render::{Film, RenderStats};
use fenestra_session::denoise::{self, DenoiseMode};

/// The denoising option.
#[derive(Args, Clone, Copy, Debug)]
pub struct DenoiseArgs {
    /// Also write OUT.denoised.exr and OUT.denoised.png: the image denoised by Intel Open
    /// Image Denoise (its RT filter, HDR), guided by albedo and normal features that the
    /// render takes beside its samples (and writes as the EXR's layers `albedo` and
    /// `normal`). MODE: accurate (default; the features prefiltered first, as Cycles does)
    /// or fast. The sidecar's "denoiser" says what ran. OIDN is installed by scripts/setup.
    #[arg(long, value_name = "MODE", num_args = 0..=1, default_missing_value = DenoiseMode::default().name())]
    pub denoise: Option<DenoiseMode>,
}

impl DenoiseArgs {
    /// Refuses a denoise OIDN cannot do here, before anything is rendered.
    pub fn check(&self) -> Result<()> {
        if self.denoise.is_some() {
            denoise::check()?;
        }
        Ok(())
    }

    /// The film's image denoised, if asked for; `stats` then say what denoised it.
    pub fn apply(&self, film: &Film, stats: &mut RenderStats) -> Result<Option<Image>> {
        let Some(mode) = self.denoise else {
            return Ok(None);
        };
        let (image, info) = denoise::denoise_film(film, mode)?;
        stats.denoiser = Some(info);
        Ok(Some(image))
    }
}
