//! The flags made from the registry's option groups, and what they build.

use super::*;
use clap::Parser;
use fenestra_render::options::OptionError;

#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    args: IntegratorArgs,
}

fn parse(flags: &[&str]) -> Result<IntegratorArgs, clap::Error> {
    Cli::try_parse_from(std::iter::once("fenestra").chain(flags.iter().copied())).map(|c| c.args)
}

#[test]
fn flags_set_the_keys_they_are_made_from_and_nothing_else() {
    let args = parse(&[
        "--integrator",
        "sdrc",
        "--sdrc-a",
        "0.3",
        "--max-depth",
        "4",
    ])
    .expect("flags");
    assert_eq!(args.0.name, "sdrc");
    let expected = Params::new()
        .with("sdrc.a", "0.3")
        .with("path.max_depth", "4");
    assert_eq!(args.0.params, expected);
    let args = parse(&["--portals", "auto", "--no-portal-cache"]).expect("flags");
    let expected = Params::new()
        .with("portals.source", "auto")
        .with("portals.no_cache", true);
    assert_eq!(args.0.params, expected);
    assert_eq!(parse(&[]).expect("no flags").0.params, Params::new());
}

#[test]
fn every_option_has_a_flag_and_choices_are_checked_by_the_parser() {
    let mut seen = std::collections::HashSet::new();
    for (key, group, i) in flags(registry().groups()) {
        let flag = group.flag(&group.fields[i]);
        assert!(
            seen.insert(flag.clone()),
            "two options share --{flag} ({key})"
        );
    }
    assert!(seen.contains("light-selection") && seen.contains("ias-threshold"));
    let e = parse(&["--light-selection", "brightest"]).expect_err("an unknown sampler");
    assert!(
        e.to_string()
            .contains("possible values: auto, power, uniform, all, split, bvh, learned"),
        "{e}"
    );
    let e = parse(&["--ias-combine", "mean"]).expect_err("an unknown choice");
    assert!(e.to_string().contains("samples"), "{e}");
}

#[test]
fn flags_and_a_parameter_map_build_the_same_integrator() {
    let scene = fenestra_builtin::load("teapot-box").expect("built-in");
    let settings = |name: &str, params: &Params| {
        let built = registry().build(name, params, &scene).expect("builds");
        built.settings()
    };
    let flags = parse(&[
        "--integrator",
        "sdrc",
        "--sdrc-a",
        "0.3",
        "--sdrc-diffuse",
        "path",
        "--max-depth",
        "4",
        "--light-selection",
        "bvh",
        "--bvh-split",
        "8",
    ])
    .expect("flags");
    let map = Params::new()
        .with("sdrc.a", 0.3)
        .with("sdrc.diffuse", "path")
        .with("path.max_depth", 4)
        .with("light.selection", "bvh")
        .with("bvh.split", 8);
    let from_flags = settings(&flags.0.name, &flags.0.params);
    assert_eq!(from_flags, settings("sdrc", &map));
    assert_ne!(from_flags, settings("sdrc", &Params::new()));
    assert_eq!(
        from_flags["sdrc"]["a"].as_f64().map(|a| a as f32),
        Some(0.3)
    );
    assert_eq!(from_flags["light_selection"], "bvh(split 8)");
    // No flags: every option its default, the path length the scene's.
    let defaults = settings(
        "sdrc",
        &parse(&["--integrator", "sdrc"]).expect("flags").0.params,
    );
    let sdrc = serde_json::to_value(fenestra_cache::SdrcOptions::default()).expect("json");
    assert_eq!(defaults["sdrc"], sdrc);
    assert_eq!(defaults["max_depth"], scene.defaults.max_depth);
}

#[test]
fn errors_name_the_flag_and_the_key() {
    use fenestra_session::error::option_name;
    use fenestra_session::{Error, Style};
    let e = Error::Option(OptionError::new("sdrc.a", "must be positive, got 0"));
    assert_eq!(
        e.worded(Style::Flag),
        "--sdrc-a: sdrc.a must be positive, got 0"
    );
    assert_eq!(e.to_string(), "sdrc_a: sdrc.a must be positive, got 0");
    let flag = |key| option_name(key, Style::Flag);
    assert_eq!(flag("portals.source").as_deref(), Some("--portals"));
    assert_eq!(flag("path.max_depth").as_deref(), Some("--max-depth"));
}

#[test]
fn a_pbrt_integrator_directive_sets_options_under_the_command_line() {
    let scene = |integrator: &str| {
        let text = format!(
            "{integrator}\nWorldBegin\nLightSource \"point\" \"rgb I\" [1 1 1]\n\
             Shape \"sphere\" \"float radius\" 1\n"
        );
        let path = std::path::Path::new("integrator.pbrt");
        fenestra_pbrt::load_bytes(text.as_bytes(), path, false)
            .expect("scene")
            .desc
    };
    let selection = |scene: &fenestra_scene::SceneDesc, name: &str, params: &Params| {
        let built = registry().build(name, params, scene).expect("builds");
        built.settings()["light_selection"].clone()
    };
    let uniform = scene("Integrator \"path\" \"string lightsampler\" \"uniform\"");
    assert_eq!(
        uniform.defaults.options,
        [
            ("path.sides".into(), "shading".into()),
            ("light.selection".into(), "uniform".into())
        ]
    );
    assert_eq!(selection(&uniform, "af_hf", &Params::new()), "uniform");
    // Exports say it again.
    let dir = std::env::temp_dir().join(format!("fenestra-integrator-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let exported = dir.join("uniform.pbrt");
    fenestra_pbrt::export::write(&uniform, &exported).expect("export");
    let back = fenestra_pbrt::load(&exported, true)
        .expect("read back")
        .desc;
    assert_eq!(back.defaults.options, uniform.defaults.options);
    let _ = std::fs::remove_dir_all(&dir);
    // The command line wins; the scene's options are read as flags are.
    let power = Params::new().with("light.selection", "power");
    assert_eq!(selection(&uniform, "af_hf", &power), "power");
    assert_eq!(
        selection(&scene("Integrator \"path\""), "af_hf", &Params::new()),
        "auto"
    );
    let bvh = scene("Integrator \"volpath\" \"string lightsampler\" \"exhaustive\"");
    assert_eq!(selection(&bvh, "sdrc", &Params::new()), "bvh");
    // An integrator that does not sample lights by a light sampler takes no offence.
    assert!(registry().build("ias", &Params::new(), &uniform).is_ok());
    let e = fenestra_pbrt::load_bytes(
        b"Integrator \"path\" \"string lightsampler\" \"magic\"\nWorldBegin\n",
        std::path::Path::new("magic.pbrt"),
        false,
    )
    .err()
    .expect("refused");
    assert!(
        e.to_string().contains("unknown lightsampler \"magic\""),
        "{e}"
    );
}

#[test]
fn portals_auto_estimates_with_the_estimate_options_given_to_render() {
    let scene = fenestra_builtin::load("box-hole").expect("built-in");
    let flags = parse(&[
        "--integrator",
        "lp_hf",
        "--portals",
        "auto",
        "--no-portal-cache",
        "--estimate-theta",
        "5",
        "--estimate-model",
        "ellipse",
        "--estimate-photons",
        "1000",
    ])
    .expect("flags");
    assert_eq!(
        flags.0.params,
        Params::new()
            .with("portals.source", "auto")
            .with("portals.no_cache", true)
            .with("estimate.theta", "5")
            .with("estimate.model", "ellipse")
            .with("estimate.photons", "1000")
    );
    let built = registry()
        .build(&flags.0.name, &flags.0.params, &scene)
        .expect("builds");
    let estimated = &built.settings()["portals"]["estimated"];
    assert_eq!(estimated["photons"]["theta_deg"], 5.0, "{estimated}");
    assert_eq!(estimated["photons"]["target"], 1000, "{estimated}");
    assert_eq!(estimated["model"], "Ellipse", "{estimated}");
    // Unless told, the estimate is `fenestra portals`'s.
    let defaults = registry()
        .build(
            "lp_hf",
            &Params::new().with("portals.source", "auto"),
            &scene,
        )
        .expect("builds");
    assert_eq!(
        defaults.settings()["portals"]["estimated"],
        serde_json::to_value(fenestra_portals::estimate::EstimateParams::default()).expect("json")
    );
}
