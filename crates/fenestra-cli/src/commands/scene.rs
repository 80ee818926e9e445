//! `fenestra scene`: inspect a scene (counts, bounds, load time, unsupported input) and export
//! it as pbrt-v4.

use crate::support::scene_arg::{self, SceneOptions};
use anyhow::{bail, Result};
use clap::{Args, Subcommand};
use fenestra_pbrt as pbrt;
use fenestra_scene::light::{EnvironmentDesc, LightDesc};
use fenestra_scene::sky::{sky_irradiance, sun, Sky};
use fenestra_scene::{Backend, SceneDesc, ShapeKind};
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct SceneArgs {
    #[command(subcommand)]
    command: SceneCommand,
}

#[derive(Subcommand)]
enum SceneCommand {
    /// Print what a scene holds, how long it took to load and what it could not represent.
    Info {
        /// builtin:NAME, a pbrt-v4 file, or an OBJ/PLY mesh.
        scene: String,
        #[command(flatten)]
        options: SceneOptions,
        /// Print as JSON.
        #[arg(long)]
        json: bool,
    },
    /// List everything in a scene that fenestra replaces or renders its own way, grouped by
    /// geometry, materials, textures, lights, camera and rendering, one line each with its
    /// effect on the picture. Exits with status 1 when something is replaced.
    Check {
        /// A pbrt-v4 file (or an OBJ/PLY mesh, builtin:NAME).
        scene: String,
    },
    /// Write a scene as a pbrt-v4 file (large meshes and images go to a folder beside it).
    /// With --sky, the folder also holds the sky for renderers that read equirectangular
    /// maps (Blender's Cycles): sky.exr, the map `--environment sky.exr` (with the same
    /// --environment-up, -rotation and -strength) renders as --sky without its sun, and
    /// sun.json, the sun's direction in the scene, irradiance and angular diameter.
    Export {
        /// builtin:NAME, a pbrt-v4 file, or an OBJ/PLY mesh.
        scene: String,
        #[command(flatten)]
        options: SceneOptions,
        /// Output .pbrt file.
        #[arg(short, long)]
        output: PathBuf,
    },
}

pub fn run(args: SceneArgs) -> Result<()> {
    match args.command {
        SceneCommand::Info {
            scene,
            options,
            json,
        } => info(&scene, options, json),
        SceneCommand::Check { scene } => check(&scene),
        SceneCommand::Export {
            scene,
            options,
            output,
        } => {
            if output.extension().is_none_or(|e| e != "pbrt") {
                bail!("output {} must end in .pbrt", output.display());
            }
            let loaded = scene_arg::load(&scene, &options)?;
            fenestra_session::files::create_output_folder(&output)?;
            fenestra_session::files::Files::default()
                .inputs(&loaded.files, "scene file")
                .output(&output, "export")
                .folder(&pbrt::export::data_folder(&output), "export's data folder")
                .check()?;
            let written = pbrt::export::write(&loaded.desc, &output)?;
            for f in written.files {
                println!("wrote {}", f.display());
            }
            if let Some((sky, _)) = &loaded.sky {
                for f in write_sky(sky, &loaded.desc, &pbrt::export::data_folder(&output))? {
                    println!("wrote {}", f.display());
                }
            }
            for a in written.approximations {
                eprintln!("approximated: {a}");
            }
            Ok(())
        }
    }
}

/// --sky's map as `desc` holds it (lat-long in the sky's own frame, unscaled) and its sun
/// (placed, and scaled by --sun-strength and --environment-strength), into `folder`.
fn write_sky(sky: &Sky, desc: &SceneDesc, folder: &Path) -> Result<Vec<PathBuf>> {
    let environment = |l: &LightDesc| match l {
        LightDesc::Environment(e) => Some(e.clone()),
        _ => None,
    };
    let lights = || desc.lights.iter().filter_map(environment);
    let Some(image) = lights().find_map(|e| match e {
        EnvironmentDesc::Image { image, .. } => Some(image),
        _ => None,
    }) else {
        bail!("--sky left no sky map in the scene");
    };
    let sun = lights().find_map(|e| match e {
        EnvironmentDesc::Sun {
            direction,
            radiance,
            half_angle,
        } => Some((direction, radiance, half_angle)),
        _ => None,
    });
    let map = folder.join("sky.exr");
    image.write_exr(&map, &Default::default())?;
    let json = folder.join("sun.json");
    let sun = sun.map(|(direction, radiance, half_angle)| {
        // A uniform disk of angular radius a: irradiance at normal incidence L pi sin^2 a.
        let irradiance = radiance * (std::f32::consts::PI * half_angle.sin().powi(2));
        serde_json::json!({
            "direction": direction.to_array(),
            "radiance": radiance.to_array(),
            "irradiance": irradiance.to_array(),
            "angle_deg": 2.0 * half_angle.to_degrees(),
            "elevation_deg": sky.elevation_deg,
            "azimuth_deg": sky.azimuth_deg,
        })
    });
    let text = serde_json::to_string_pretty(&serde_json::json!({ "sun": sun }))?;
    fenestra_core::fs::write_atomically(&json, |tmp| std::fs::write(tmp, &text))?;
    Ok(vec![map, json])
}

fn info(scene: &str, options: SceneOptions, json: bool) -> Result<()> {
    let loaded = scene_arg::load_quietly(scene, &options)?;
    let d = &loaded.desc;
    let triangles: usize = d
        .shapes
        .iter()
        .map(|s| match &s.kind {
            ShapeKind::Mesh(m) => m.indices.len(),
            _ => 0,
        })
        .sum();
    let count = |f: fn(&LightDesc) -> bool| d.lights.iter().filter(|l| f(l)).count();
    let (points, spots, distant, suns, env) = (
        count(|l| matches!(l, LightDesc::Point { .. })),
        count(|l| matches!(l, LightDesc::Spot { .. })),
        count(|l| matches!(l, LightDesc::Distant { .. })),
        count(|l| matches!(l, LightDesc::Environment(EnvironmentDesc::Sun { .. }))),
        count(
            |l| matches!(l, LightDesc::Environment(e) if !matches!(e, EnvironmentDesc::Sun { .. })),
        ),
    );
    // As light sampling counts them: one light per emitting triangle, sphere and disk
    // (fenestra_render::light::Lights), beside the shapes they belong to.
    let emitting: Vec<_> = d
        .shapes
        .iter()
        .filter(|s| s.emission.is_some_and(|e| !e.radiance.is_black()) && s.area() > 0.0)
        .collect();
    let emitters: usize = emitting.iter().map(|s| s.primitive_count()).sum();
    let lights = emitters + d.lights.len();
    let mut lo = fenestra_core::Vec3::splat(f32::INFINITY);
    let mut hi = -lo;
    for s in &d.shapes {
        for p in 0..s.primitive_count() {
            let (a, b) = s.primitive_bounds(p);
            lo = lo.min(a);
            hi = hi.max(b);
        }
    }
    let sky = (loaded.sky.as_ref()).map(|(sky, strength)| sky_report(sky, *strength, d));
    let v = serde_json::json!({
        "scene": scene,
        "name": d.name,
        "load_seconds": loaded.seconds,
        "shapes": d.shapes.len(),
        "triangles": triangles,
        "materials": d.materials.len(),
        "lights": lights,
        "area_lights": emitters,
        "emitting_shapes": emitting.len(),
        "point_lights": points,
        "spot_lights": spots,
        "distant_lights": distant,
        "suns": suns,
        "environments": env,
        "portals": d.portals.len(),
        "bounds": [lo.to_array(), hi.to_array()],
        "resolution": [d.defaults.width, d.defaults.height],
        "spp": d.defaults.spp,
        "max_depth": d.defaults.max_depth,
        "cameras": loaded.cameras,
        "sky": sky,
        "warnings": loaded.warnings(),
    });
    if json {
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!("{} ({scene}), loaded in {:.3} s", d.name, loaded.seconds);
    println!(
        "  {} shapes, {triangles} triangles, {} materials",
        d.shapes.len(),
        d.materials.len()
    );
    println!(
        "  lights: {lights} ({emitters} area in {} emitting shape{}, {points} point, {spots} spot, \
         {distant} distant, {env} environment{}); {} portals",
        emitting.len(),
        if emitting.len() == 1 { "" } else { "s" },
        if suns > 0 { ", the sun" } else { "" },
        d.portals.len()
    );
    println!("  bounds {lo} .. {hi}");
    println!(
        "  defaults: {}x{}, {} spp, path length {}",
        d.defaults.width, d.defaults.height, d.defaults.spp, d.defaults.max_depth
    );
    if !loaded.cameras.is_empty() {
        let named: Vec<String> = loaded
            .cameras
            .iter()
            .enumerate()
            .map(|(i, c)| format!("{i}: {c}"))
            .collect();
        println!("  cameras (--camera): {}", named.join(", "));
    }
    if let Some((sky, _)) = &loaded.sky {
        let r = &v["sky"];
        let klux = |key: &str| r[key].as_f64().unwrap_or(0.0) / 1e3;
        println!(
            "  sky: turbidity {}, ground albedo {}, the sun {:.1} degrees up at azimuth {:.1}: \
             {:.1} klux direct normal; on the ground {:.1} klux from the sun, {:.1} klux from the sky",
            sky.turbidity,
            sky.albedo,
            sky.elevation_deg,
            sky.azimuth_deg,
            klux("sun_direct_normal_lux"),
            klux("sun_horizontal_lux"),
            klux("sky_horizontal_lux"),
        );
    }
    for w in &loaded.warnings() {
        println!("  warning: {w}");
    }
    Ok(())
}

/// `scene check`: the report, and whether anything is replaced (exit status 1).
/// The scene is built as `render` builds it, so what render would refuse (non-finite or
/// astronomically large geometry, negative or infinite light) is reported too.
fn check(scene: &str) -> Result<()> {
    let loaded = scene_arg::load_quietly(scene, &SceneOptions::default())?;
    let refused = fenestra_scene::Scene::build(loaded.desc.clone(), Backend::default()).err();
    print!("{}", check_report(scene, &loaded, refused.as_ref()));
    if !loaded.substitutions.is_empty() || !loaded.other.is_empty() || refused.is_some() {
        std::process::exit(1);
    }
    Ok(())
}

fn check_report(
    scene: &str,
    loaded: &fenestra_session::LoadedScene,
    refused: Option<&fenestra_scene::SceneError>,
) -> String {
    use std::fmt::Write;
    let (subs, notes) = (&loaded.substitutions, &loaded.notes);
    let mut out = String::new();
    let as_written = subs.is_empty() && notes.is_empty() && loaded.other.is_empty();
    let _ = writeln!(
        out,
        "{scene}: {} replaced, {} rendered fenestra's own way{}",
        kinds(subs.len()),
        kinds(notes.len()),
        match (refused, as_written) {
            (Some(_), _) => ": render refuses it",
            (None, true) => ": read as written",
            (None, false) => "",
        }
    );
    if let Some(e) = refused {
        let _ = writeln!(out, "\nRefused\n  {e}");
    }
    let mut topics: Vec<pbrt::Topic> = subs.iter().chain(notes).map(|w| w.topic).collect();
    topics.sort();
    topics.dedup();
    for topic in topics {
        let _ = writeln!(out, "\n{}", capitalised(&topic.to_string()));
        for (label, list) in [("replaced", subs), ("own way ", notes)] {
            for w in list.iter().filter(|w| w.topic == topic) {
                let times = match w.count {
                    1 => String::new(),
                    n => format!(", {n} times"),
                };
                let _ = writeln!(out, "  {label}  {}  [{}{times}]", w.what, w.first);
            }
        }
    }
    if !loaded.other.is_empty() {
        let _ = writeln!(out, "\nOther");
        for w in &loaded.other {
            let _ = writeln!(out, "  {w}");
        }
    }
    out
}

fn kinds(n: usize) -> String {
    match n {
        0 => "nothing".into(),
        1 => "1 kind of input".into(),
        n => format!("{n} kinds of input"),
    }
}

fn capitalised(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map(|f| f.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

/// What --sky sends: its parameters and illuminances (lux, times `strength`), the sky's from
/// the map baked into `desc`.
fn sky_report(sky: &Sky, strength: f32, desc: &SceneDesc) -> serde_json::Value {
    let lux = |e: fenestra_core::Rgb| f64::from(e.luminance() * strength) * 683.0;
    let map = desc.lights.iter().find_map(|l| match l {
        LightDesc::Environment(EnvironmentDesc::Image { image, .. }) => Some(image),
        _ => None,
    });
    serde_json::json!({
        "turbidity": sky.turbidity,
        "albedo": sky.albedo,
        "sun_elevation_deg": sky.elevation_deg,
        "sun_azimuth_deg": sky.azimuth_deg,
        "sun_direct_normal_lux": lux(sun::irradiance(sky.elevation_deg, sky.turbidity)),
        "sun_horizontal_lux": lux(sky.sun_irradiance()),
        "sky_horizontal_lux": map.map(|m| lux(sky_irradiance(m))),
    })
}
