//! Relighting a precomputed sequence frame by frame, for the batch renderer and the viewer:
//! the sequence's scene posed at the frame and lit by a lights file, the frame's transfer
//! read from its file (kept in memory up to a budget, so that playback reads each frame once),
//! and the relit image.

use crate::error::RelightError;
use crate::frame::FrameTransfer;
use crate::frame_file;
use crate::gather::Gather;
use crate::image::{relit_image, Relighting};
use crate::lights_file::LightsFile;
use crate::sequence::AnimatedScene;
use crate::store::Store;
use fenestra_core::image::Image;
use fenestra_core::Rgb;
use fenestra_render::RenderScene;
use fenestra_scene::{Backend, Scene};
use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Instant;

/// A relit frame.
pub struct RelitFrame {
    pub width: u32,
    pub height: u32,
    pub direct: Vec<Rgb>,
    pub indirect: Vec<Rgb>,
    /// Seconds the relighting took (the scene posed, lit and built, the gather samples posed
    /// and lit, transfer, direct light at the pixels; not reading the frame's file).
    pub seconds: f64,
}

impl RelitFrame {
    /// Its image: direct and indirect light, or the indirect alone.
    pub fn image(&self, indirect_only: bool) -> Image {
        let mut image = Image::new(self.width as usize, self.height as usize);
        for (i, p) in image.pixels.iter_mut().enumerate() {
            *p = if indirect_only {
                self.indirect[i]
            } else {
                self.direct[i] + self.indirect[i]
            };
        }
        image
    }
}

/// A sequence ready to relight.
pub struct Player {
    pub store: Store,
    pub animated: AnimatedScene,
    gather: Gather,
    relighting: Relighting,
    /// Frames read, and the bytes they hold, up to `budget`.
    cache: BTreeMap<u32, Arc<FrameTransfer>>,
    cached_bytes: usize,
    budget: usize,
}

/// The scene of frame `f`, lit by `lights` if given.
pub fn frame_scene(
    animated: &AnimatedScene,
    f: u32,
    lights: Option<&LightsFile>,
) -> Result<RenderScene, RelightError> {
    let mut desc = animated.at(f);
    if let Some(l) = lights {
        desc.lights = l.apply(&desc.lights);
    }
    Scene::build(desc, Backend::default())
        .map(RenderScene::new)
        .map_err(|e| RelightError::Frame(format!("frame {f}: invalid scene: {e}")))
}

impl Player {
    /// The sequence of `store` (whose scene and animation are `animated`), relit with
    /// `light_samples` samples per area light, keeping up to `budget` bytes of frames.
    pub fn new(
        store: Store,
        animated: AnimatedScene,
        light_samples: u32,
        budget: usize,
    ) -> Result<Self, RelightError> {
        let rest = frame_scene(&animated, 0, None)?;
        let gather = Gather::new(&rest, store.manifest.gather, store.manifest.seed);
        let relighting = Relighting {
            light_samples: light_samples.max(1),
            seed: store.manifest.seed,
        };
        Ok(Player {
            store,
            animated,
            gather,
            relighting,
            cache: BTreeMap::new(),
            cached_bytes: 0,
            budget,
        })
    }

    /// Frame `f`'s transfer.
    fn transfer(&mut self, f: u32) -> Result<Arc<FrameTransfer>, RelightError> {
        if let Some(t) = self.cache.get(&f) {
            return Ok(t.clone());
        }
        let (_, t) = frame_file::read(&self.store.frame_path(f))
            .map_err(|e| RelightError::Frame(e.to_string()))?;
        let t = Arc::new(t);
        let bytes = t.bytes();
        if self.cached_bytes + bytes <= self.budget {
            self.cached_bytes += bytes;
            self.cache.insert(f, t.clone());
        }
        Ok(t)
    }

    /// Frame `f` relit by `lights`.
    pub fn relight(&mut self, f: u32, lights: &LightsFile) -> Result<RelitFrame, RelightError> {
        if f >= self.store.manifest.frames {
            return Err(RelightError::Frame(format!(
                "frame {f} is not in the sequence (0 to {})",
                self.store.manifest.frames - 1
            )));
        }
        let transfer = self.transfer(f)?;
        let start = Instant::now();
        let scene = frame_scene(&self.animated, f, Some(lights))?;
        let posed = self.gather.posed(&scene);
        let (direct, indirect) = relit_image(&scene, &posed, &transfer, &self.relighting);
        Ok(RelitFrame {
            width: transfer.width,
            height: transfer.height,
            direct,
            indirect,
            seconds: start.elapsed().as_secs_f64(),
        })
    }
}
