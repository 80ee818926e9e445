//! The `fenestra` command line.

use fenestra_cli::commands::{
    bench, compare, lpca, merge, portals, prt, raybench, reference, relight, render, scene, split,
};

use clap::{Parser, Subcommand};
use fenestra_session::registry;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "fenestra",
    version,
    about = "Physically based Monte Carlo renderer: variance reduction through coherence"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to linear EXR, with a tone-mapped PNG and a JSON sidecar beside it.
    Render(render::RenderArgs),
    /// Render a high-sample reference, or reuse the cached one made with the same scene
    /// content, settings and resolution.
    Reference(reference::ReferenceArgs),
    /// Merge the pieces of a split render (`render --samples`, `--crop`) into the image one
    /// render of them all makes, bit for bit.
    Merge(merge::MergeArgs),
    /// Cut a render into parts (sample ranges or tiles) and write it as a job for a
    /// distributed engine: Open Job Description or Slurm; its last step merges the parts.
    Split(split::SplitArgs),
    /// Error, relative error and efficiency of images against a reference.
    Compare(compare::CompareArgs),
    /// Run a bench suite (TOML) and write its report (HTML, plots, tables).
    Bench(bench::BenchArgs),
    /// Compress a matrix (NPY) with k-means, SortMeans, LPCA or SortCluster-LPCA.
    Lpca(lpca::LpcaArgs),
    /// Generate a synthetic BTF-like matrix (apparent-BRDF arrangement) as NPY.
    Btf(lpca::BtfArgs),
    /// Precomputed radiance transfer matrix (vertices x 6R^2 cubemap lights) of a glossy
    /// self-shadowing mesh, as NPY.
    Prt(prt::PrtArgs),
    /// Measure closest-hit and shadow-ray throughput of the ray-query backends.
    Raybench(raybench::RaybenchArgs),
    /// Estimate light portals (seed 000): photon cone-beams, DBSCAN, RANSAC planes, covering
    /// ellipses or rectangles; writes portals.json and a picture of them.
    Portals(portals::PortalsArgs),
    /// Inspect a scene or export it as pbrt-v4.
    Scene(scene::SceneArgs),
    /// Relight an animation (seed 003 ch. 4): precompute its light transfer frame by frame,
    /// then render it under other lights.
    Relight(relight::RelightArgs),
    /// List the built-in scenes and the integrators.
    List {
        /// The integrators, light samplers and every option with its flag, keyword, help and
        /// default, as JSON (what front ends such as the Blender add-on build their settings
        /// from).
        #[arg(long)]
        json: bool,
    },
}

fn main() -> ExitCode {
    // Like other Unix tools, end quietly when the reader of our output goes away
    // (`fenestra scene info ... | head`) instead of panicking on a failed print.
    #[cfg(unix)]
    // SAFETY: restoring the default disposition of SIGPIPE before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    let result = match cli.command {
        // The conventional exit status after SIGINT, once what was done is written.
        Command::Render(args) => match render::run(args) {
            Ok(true) => return ExitCode::from(130),
            other => other.map(|_| ()),
        },
        Command::Reference(args) => reference::run(args),
        Command::Merge(args) => merge::run(args),
        Command::Relight(args) => relight::run(args),
        Command::Split(args) => split::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Bench(args) => match bench::run(args) {
            Ok(true) => return ExitCode::from(130),
            other => other.map(|_| ()),
        },
        Command::Lpca(args) => lpca::run(args),
        Command::Btf(args) => lpca::btf(args),
        Command::Prt(args) => prt::run(args),
        Command::Raybench(args) => raybench::run(args),
        Command::Scene(args) => scene::run(args),
        Command::Portals(args) => match portals::run(args) {
            Ok(true) => return ExitCode::from(130),
            other => other.map(|_| ()),
        },
        Command::List { json: true } => {
            let mut catalogue = fenestra_session::catalogue();
            catalogue["scenes"] = fenestra_builtin::SCENES
                .iter()
                .map(|(name, about)| serde_json::json!({"name": name, "about": about}))
                .collect();
            println!("{catalogue}");
            Ok(())
        }
        Command::List { json: false } => {
            println!("built-in scenes (use as builtin:NAME):");
            for (name, what) in fenestra_builtin::SCENES {
                println!("  {name:<14} {what}");
            }
            println!("integrators (--integrator NAME):");
            for e in registry().integrators() {
                println!("  {:<14} {}", e.name, e.about);
            }
            println!("light samplers (--light-selection NAME):");
            for e in registry().light_samplers() {
                println!("  {:<14} {}", e.name, e.about);
            }
            Ok(())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // A session's refusal reached here through `?`: name its settings by their flags.
            let e = e
                .downcast::<fenestra_session::Error>()
                .map_or_else(|e| e, fenestra_cli::flagged);
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
