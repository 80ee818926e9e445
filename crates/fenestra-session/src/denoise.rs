//! Denoising with Intel Open Image Denoise 2 (OIDN): its `RT` filter, HDR, guided by the
//! render's albedo and normal features.
//!
//! OIDN is loaded when a denoise is first asked for, not linked: fenestra builds, renders and
//! tests on a machine without it, and only a denoise there fails, saying how to get it. The
//! library is looked for in `$FENESTRA_OIDN` (a folder), then in
//! `~/.cache/fenestra/oidn/lib`, where `scripts/setup` puts the official libraries from
//! PyPI's `pyoidn` wheel, then on the system's library path.

use fenestra_core::image::Image;
use fenestra_core::Rgb;
use fenestra_render::Film;
use libloading::Library;
use std::ffi::{c_char, c_int, c_void, CStr};
use std::path::PathBuf;
use std::sync::OnceLock;

/// The library's file name (OIDN 2's soname).
const LIBRARY: &str = "libOpenImageDenoise.so.2";

/// How the features guide the filter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DenoiseMode {
    /// The albedo and normal are denoised first, then guide the image as noise-free
    /// (OIDN's `cleanAux`; Cycles' "accurate" prefilter): the sharpest result, three filter
    /// runs.
    #[default]
    Accurate,
    /// The features guide the image as they are, noise and all: one filter run.
    Fast,
}

impl DenoiseMode {
    /// Its name: `accurate` or `fast`.
    pub fn name(self) -> &'static str {
        match self {
            DenoiseMode::Accurate => "accurate",
            DenoiseMode::Fast => "fast",
        }
    }
}

impl DenoiseMode {
    /// The mode `name` names, or the default (`None`).
    pub fn named(name: Option<&str>) -> Result<Self, String> {
        name.map_or(Ok(DenoiseMode::default()), str::parse)
    }
}

impl std::str::FromStr for DenoiseMode {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "accurate" => Ok(DenoiseMode::Accurate),
            "fast" => Ok(DenoiseMode::Fast),
            _ => Err(format!(
                "unknown denoise mode '{s}': accurate (the features prefiltered) or fast"
            )),
        }
    }
}

/// Why a denoise failed.
#[derive(Debug, thiserror::Error)]
pub enum DenoiseError {
    /// OIDN is not installed where fenestra looks.
    #[error("Intel Open Image Denoise 2 was not found (looked for {LIBRARY} in {looked}): run scripts/setup, which installs it from PyPI's pyoidn wheel, or set FENESTRA_OIDN to the folder that holds {LIBRARY}")]
    Missing {
        /// Where it looked, and why each failed.
        looked: String,
    },
    /// OIDN refused or failed.
    #[error("Open Image Denoise failed: {0}")]
    Failed(String),
    /// The features are not the image's size.
    #[error("the features are {0}x{1}, the image {2}x{3}")]
    Size(usize, usize, usize, usize),
}

/// What denoised an image: for the sidecar.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct DenoiserInfo {
    /// "Intel Open Image Denoise".
    pub denoiser: String,
    /// Its version, as the library reports it ("2.5.1").
    pub version: String,
    /// The device it ran on ("cpu").
    pub device: String,
    /// The mode ([`DenoiseMode::name`]).
    pub mode: String,
    /// Whether albedo and normal features guided it.
    pub features: bool,
    /// Where the library was loaded from.
    pub library: String,
    /// Seconds the filter runs took.
    pub time_s: f64,
}

type Handle = *mut c_void;

/// The part of OIDN's C API fenestra calls (oidn.h of OIDN 2).
struct Api {
    library: PathBuf,
    new_device: unsafe extern "C" fn(c_int) -> Handle,
    commit_device: unsafe extern "C" fn(Handle),
    release_device: unsafe extern "C" fn(Handle),
    device_error: unsafe extern "C" fn(Handle, *mut *const c_char) -> c_int,
    device_int: unsafe extern "C" fn(Handle, *const c_char) -> c_int,
    new_filter: unsafe extern "C" fn(Handle, *const c_char) -> Handle,
    release_filter: unsafe extern "C" fn(Handle),
    set_image: unsafe extern "C" fn(
        Handle,
        *const c_char,
        *mut c_void,
        c_int,
        usize,
        usize,
        usize,
        usize,
        usize,
    ),
    set_bool: unsafe extern "C" fn(Handle, *const c_char, bool),
    commit_filter: unsafe extern "C" fn(Handle),
    execute_filter: unsafe extern "C" fn(Handle),
    /// Kept loaded for the process's life: the function pointers above point into it.
    _library: Library,
}

const DEVICE_TYPE_CPU: c_int = 1;
const FORMAT_FLOAT3: c_int = 3;

/// The folders OIDN is looked for in, in order; `None`: the system's library path.
fn candidates() -> Vec<Option<PathBuf>> {
    let mut out = Vec::new();
    if let Some(dir) = std::env::var_os("FENESTRA_OIDN") {
        let dir = PathBuf::from(dir);
        out.push(Some(dir.join("lib")));
        out.push(Some(dir));
    }
    if let Some(home) = std::env::var_os("HOME") {
        out.push(Some(PathBuf::from(home).join(".cache/fenestra/oidn/lib")));
    }
    out.push(None);
    out
}

fn load() -> Result<Api, String> {
    let mut looked = Vec::new();
    for dir in candidates() {
        let path = dir
            .as_ref()
            .map_or(PathBuf::from(LIBRARY), |d| d.join(LIBRARY));
        if dir.is_some() && !path.exists() {
            looked.push(format!(
                "{} (absent)",
                path.parent().unwrap_or(&path).display()
            ));
            continue;
        }
        // SAFETY: loading OIDN runs its initialisers, which only register its devices.
        match unsafe { Library::new(&path) } {
            Ok(lib) => return bind(lib, path).map_err(|e| format!("{e}")),
            Err(e) => looked.push(match &dir {
                Some(d) => format!("{} ({e})", d.display()),
                None => "the system's library path".into(),
            }),
        }
    }
    Err(looked.join(", "))
}

fn bind(lib: Library, library: PathBuf) -> Result<Api, libloading::Error> {
    // SAFETY: each symbol is given the signature oidn.h (OIDN 2) declares for it.
    unsafe {
        Ok(Api {
            library,
            new_device: *lib.get(b"oidnNewDevice\0")?,
            commit_device: *lib.get(b"oidnCommitDevice\0")?,
            release_device: *lib.get(b"oidnReleaseDevice\0")?,
            device_error: *lib.get(b"oidnGetDeviceError\0")?,
            device_int: *lib.get(b"oidnGetDeviceInt\0")?,
            new_filter: *lib.get(b"oidnNewFilter\0")?,
            release_filter: *lib.get(b"oidnReleaseFilter\0")?,
            set_image: *lib.get(b"oidnSetSharedFilterImage\0")?,
            set_bool: *lib.get(b"oidnSetFilterBool\0")?,
            commit_filter: *lib.get(b"oidnCommitFilter\0")?,
            execute_filter: *lib.get(b"oidnExecuteFilter\0")?,
            _library: lib,
        })
    }
}

fn api() -> Result<&'static Api, DenoiseError> {
    static API: OnceLock<Result<Api, String>> = OnceLock::new();
    API.get_or_init(load)
        .as_ref()
        .map_err(|looked| DenoiseError::Missing {
            looked: looked.clone(),
        })
}

/// Whether OIDN can be loaded here: the reason if not (to refuse a denoise before a long
/// render rather than after it).
pub fn check() -> Result<(), DenoiseError> {
    api().map(|_| ())
}

/// An OIDN CPU device, released when dropped.
struct Device<'a> {
    api: &'a Api,
    handle: Handle,
}

impl<'a> Device<'a> {
    fn new(api: &'a Api) -> Result<Self, DenoiseError> {
        // SAFETY: the calls follow oidn.h; a null device is refused before use.
        let handle = unsafe { (api.new_device)(DEVICE_TYPE_CPU) };
        if handle.is_null() {
            return Err(DenoiseError::Failed("no CPU device".into()));
        }
        let device = Device { api, handle };
        unsafe { (api.commit_device)(handle) };
        device.check()?;
        Ok(device)
    }

    /// The device's pending error, if any.
    fn check(&self) -> Result<(), DenoiseError> {
        let mut message: *const c_char = std::ptr::null();
        // SAFETY: OIDN returns a NUL-terminated message it owns, or null.
        let code = unsafe { (self.api.device_error)(self.handle, &mut message) };
        if code == 0 {
            return Ok(());
        }
        let text = match message.is_null() {
            true => format!("error {code}"),
            false => unsafe { CStr::from_ptr(message) }
                .to_string_lossy()
                .into_owned(),
        };
        Err(DenoiseError::Failed(text))
    }

    fn version(&self) -> String {
        // SAFETY: "version" is a read-only device parameter (major * 10000 + minor * 100 +
        // patch).
        let v = unsafe { (self.api.device_int)(self.handle, c"version".as_ptr()) };
        format!("{}.{}.{}", v / 10000, v / 100 % 100, v % 100)
    }

    /// Runs one RT filter over `size` images: `images` (parameter name, pixels: a live
    /// width x height RGB f32 buffer, "output" among them, written in place), with the
    /// boolean parameters `flags`.
    fn run(
        &self,
        (width, height): (usize, usize),
        images: &[(&CStr, *mut [f32; 3])],
        flags: &[(&CStr, bool)],
    ) -> Result<(), DenoiseError> {
        let api = self.api;
        // SAFETY: the filter is made and released here; the buffers it is given outlast its
        // execution (the callers' slices).
        unsafe {
            let filter = (api.new_filter)(self.handle, c"RT".as_ptr());
            if filter.is_null() {
                self.check()?;
                return Err(DenoiseError::Failed("no RT filter".into()));
            }
            for &(name, pixels) in images {
                let format = FORMAT_FLOAT3;
                (api.set_image)(
                    filter,
                    name.as_ptr(),
                    pixels.cast(),
                    format,
                    width,
                    height,
                    0,
                    0,
                    0,
                );
            }
            for &(name, value) in flags {
                (api.set_bool)(filter, name.as_ptr(), value);
            }
            (api.commit_filter)(filter);
            (api.execute_filter)(filter);
            let done = self.check();
            (api.release_filter)(filter);
            done
        }
    }
}

impl Drop for Device<'_> {
    fn drop(&mut self) {
        // SAFETY: the device was made by `new` and is released once.
        unsafe { (self.api.release_device)(self.handle) }
    }
}

/// OIDN's input: finite, non-negative values (a NaN would spread through the network).
fn pixels(image: &Image, lo: f32) -> Vec<[f32; 3]> {
    let clean = |v: f32| if v.is_finite() { v.max(lo) } else { 0.0 };
    (image.pixels.iter())
        .map(|p| [clean(p.r), clean(p.g), clean(p.b)])
        .collect()
}

/// `color` denoised by OIDN's RT filter, guided by `features` (albedo, normal) if given, as
/// `mode` says; and what denoised it.
pub fn denoise(
    color: &Image,
    features: Option<(&Image, &Image)>,
    mode: DenoiseMode,
) -> Result<(Image, DenoiserInfo), DenoiseError> {
    let size = (color.width, color.height);
    for f in features.iter().flat_map(|(a, n)| [a, n]) {
        if (f.width, f.height) != size {
            return Err(DenoiseError::Size(f.width, f.height, size.0, size.1));
        }
    }
    let api = api()?;
    let started = std::time::Instant::now();
    let device = Device::new(api)?;
    let mut out = pixels(color, 0.0);
    let color = out.as_mut_ptr();
    let mut images = vec![(c"color", color), (c"output", color)];
    let mut flags = vec![(c"hdr", true)];
    // Kept alive until the filter has run.
    let mut guides = features.map(|(a, n)| (pixels(a, 0.0), pixels(n, -1.0)));
    if let Some((albedo, normal)) = guides.as_mut() {
        let clean = mode == DenoiseMode::Accurate;
        if clean {
            // Prefiltered: each guide denoised on its own, in place.
            for (name, guide) in [
                (c"albedo", albedo.as_mut_ptr()),
                (c"normal", normal.as_mut_ptr()),
            ] {
                device.run(size, &[(name, guide), (c"output", guide)], &[])?;
            }
        }
        images.extend([
            (c"albedo", albedo.as_mut_ptr()),
            (c"normal", normal.as_mut_ptr()),
        ]);
        flags.push((c"cleanAux", clean));
    }
    device.run(size, &images, &flags)?;
    let info = DenoiserInfo {
        denoiser: "Intel Open Image Denoise".into(),
        version: device.version(),
        device: "cpu".into(),
        mode: mode.name().into(),
        features: features.is_some(),
        library: api.library.display().to_string(),
        time_s: started.elapsed().as_secs_f64(),
    };
    let mut image = Image::new(size.0, size.1);
    for (dst, p) in image.pixels.iter_mut().zip(out) {
        *dst = Rgb::new(p[0], p[1], p[2]);
    }
    Ok((image, info))
}

/// The image of `film` denoised as `mode` says, guided by the film's features if it took
/// them; and what denoised it, as the sidecar records it.
pub fn denoise_film(
    film: &Film,
    mode: DenoiseMode,
) -> Result<(Image, serde_json::Value), DenoiseError> {
    let features = film.feature_images();
    let guides = features.as_ref().map(|(a, n)| (a, n));
    let (image, info) = denoise(&film.image(), guides, mode)?;
    let info = serde_json::to_value(info).map_err(|e| DenoiseError::Failed(e.to_string()))?;
    Ok((image, info))
}
