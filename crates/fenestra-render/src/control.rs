//! What the caller of a render controls while it runs: cancellation (Ctrl-C), progress
//! reports, and a hook after every pass (convergence curves, stopping at a target error).

use crate::film::Film;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Receives progress: `start` once per stage with its total work (samples, photons, if
/// known), then `advance`; `note` for a line of information (what a preparation found).
pub trait Progress: Sync {
    /// A new stage begins, with `total` units of work if known.
    fn start(&self, _total: Option<u64>) {}
    /// `units` more units of work are done.
    fn advance(&self, _units: u64) {}
    /// A line of information for the user.
    fn note(&self, _text: &str) {}
}

/// Progress that goes nowhere.
pub struct NoProgress;
impl Progress for NoProgress {}

/// Called after every completed pass with the film and the seconds since the render began;
/// returns whether to go on (a measurement can stop a render once it reaches a target error).
pub type PassHook<'a> = &'a (dyn Fn(&Film, f64) -> bool + Sync);

/// A hook that sees the film whenever it holds more of the image, with the render's elapsed
/// seconds.
pub type ProgressHook<'a> = &'a (dyn Fn(&Film, f64) + Sync);

/// Progress reporting, cancellation and a per-pass hook for one render, and its clock: the
/// render's time runs from the control's creation, so preparation counts in it.
#[derive(Clone, Copy)]
pub struct RenderControl<'a> {
    /// Set (by a Ctrl-C handler) to stop: the work done so far is kept.
    pub cancel: &'a AtomicBool,
    /// Where progress goes.
    pub progress: &'a dyn Progress,
    /// Called after every pass.
    pub on_pass: Option<PassHook<'a>>,
    /// Called whenever the film holds more of the image: after every pass, and, for
    /// integrators that render each block to completion, after every block (one call at a
    /// time). For watching a render; it cannot stop it.
    pub on_progress: Option<ProgressHook<'a>>,
    /// The render's time budget in seconds on this control's clock, preparation included
    /// (set from the render's settings when it starts): a preparation keeps to a share of it.
    pub time_limit: Option<f64>,
    /// The whole image's width and height in pixels (set from the film when the render
    /// starts): a preparation that looks through the camera takes the image's aspect.
    pub image_size: Option<(u32, u32)>,
    pub(crate) started: Instant,
}

/// Never set: the cancel flag of unattended renders.
static NEVER: AtomicBool = AtomicBool::new(false);

impl RenderControl<'static> {
    /// A control for renders nobody watches (tests, scripts): no cancellation, no
    /// progress, no hook.
    pub fn unattended() -> Self {
        RenderControl::new(&NEVER, &NoProgress)
    }
}

impl<'a> RenderControl<'a> {
    /// A control whose clock starts now.
    pub fn new(cancel: &'a AtomicBool, progress: &'a dyn Progress) -> Self {
        RenderControl {
            cancel,
            progress,
            on_pass: None,
            on_progress: None,
            time_limit: None,
            image_size: None,
            started: Instant::now(),
        }
    }

    /// Whether the render was asked to stop.
    pub fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// Seconds since the control was made.
    pub fn elapsed(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }
}
