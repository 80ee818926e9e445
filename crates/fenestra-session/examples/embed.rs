//! fenestra embedded in a program: a built-in scene under a clear sky rendered through the
//! session API, then written as `fenestra render` writes its images (EXR, PNG, JSON).
//!
//!     cargo run --release -p fenestra-session --example embed -- out/embedded.exr

use fenestra_render::output::{self, Extras};
use fenestra_session::files::{check_exr, render_outputs, Beside, Files};
use fenestra_session::{
    render, IntegratorChoice, JobSpec, Lighting, Placement, Resolution, SceneRequest, SkyRequest,
};
use std::path::PathBuf;

/// Renders `builtin:box-hole` lit by the sky through its opening, by light portals, to `exr`.
pub fn embed(exr: &std::path::Path) -> fenestra_session::Result<fenestra_render::RenderStats> {
    let scene = SceneRequest {
        lighting: Lighting::Sky {
            sky: SkyRequest::default(),
            placement: Placement::default(),
        },
        ..SceneRequest::new("builtin:box-hole")
    };
    let spec = JobSpec {
        integrator: IntegratorChoice::named("lp_hf"),
        spp: Some(8),
        resolution: Some(Resolution::new(64, 64)?),
        ..JobSpec::default()
    };
    check_exr(exr)?;
    render_outputs(&mut Files::default(), exr, Beside::default()).check()?;
    let done = render(&scene, &spec)?;
    output::write_render(exr, &done.film, &done.stats, &Extras::default())
        .map_err(anyhow::Error::from)?;
    Ok(done.stats)
}

#[allow(dead_code)] // Not when a test includes this file for `embed`.
fn main() -> std::process::ExitCode {
    let exr = std::env::args_os()
        .nth(1)
        .map_or_else(|| PathBuf::from("embedded.exr"), PathBuf::from);
    match embed(&exr) {
        Ok(stats) => {
            println!("{}", stats.summary());
            std::process::ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
