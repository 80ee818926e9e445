//! The integrators this binary offers and their command-line flags. Each crate registers its
//! integrators and light samplers with their option groups; the flags are made from those
//! groups (`sdrc.a` is `--sdrc-a`), so an option's default, help and checks live only in the
//! crate that owns it.

use clap::builder::PossibleValuesParser;
use clap::parser::ValueSource;
use clap::{Arg, ArgAction, ArgMatches, Command};
use fenestra_render::options::{Kind, OptionError, Params};
use fenestra_render::registry::{Group, Registry};
use std::sync::LazyLock;

/// Every integrator and light sampler of this binary.
pub fn registry() -> &'static Registry {
    static REGISTRY: LazyLock<Registry> = LazyLock::new(|| {
        let mut registry = Registry::new();
        fenestra_render::integrator::register(&mut registry);
        fenestra_manylights::register(&mut registry);
        fenestra_cache::register(&mut registry);
        fenestra_portals::register(&mut registry);
        registry
    });
    &REGISTRY
}

/// Which integrator, and the options given for it on the command line.
#[derive(Clone, Debug)]
pub struct IntegratorArgs {
    /// The integrator's name.
    pub integrator: String,
    /// The options given (flags left out take their defaults).
    pub params: Params,
}

/// The default integrator.
const DEFAULT: &str = "af_hf";

/// Every option flag: (key, group, field index).
fn flags() -> impl Iterator<Item = (String, &'static Group, usize)> {
    registry().groups().iter().flat_map(|g| {
        (0..g.fields.len()).map(move |i| (format!("{}.{}", g.name, g.fields[i].name), g, i))
    })
}

/// The command-line flag of option `key` (`--sdrc-a` of `sdrc.a`).
pub fn flag_of(key: &str) -> Option<String> {
    flags()
        .find(|(k, _, _)| k == key)
        .map(|(_, g, i)| format!("--{}", g.flag(&g.fields[i])))
}

/// An option's error as the command line names it: by its flag, then its key.
pub fn flag_error(e: &OptionError) -> String {
    match flag_of(&e.key) {
        Some(flag) => format!("{flag}: {e}"),
        None => e.to_string(),
    }
}

impl IntegratorArgs {
    /// The portals file given, if one was (not `auto`).
    pub fn portals_file(&self) -> Option<&str> {
        let given = self.params.iter().find(|(k, _)| *k == "portals.source");
        given.and_then(|(_, v)| v.as_str()).filter(|&p| p != "auto")
    }
}

impl clap::FromArgMatches for IntegratorArgs {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let mut params = Params::new();
        for (key, group, i) in flags() {
            if matches.value_source(&key) != Some(ValueSource::CommandLine) {
                continue;
            }
            match group.fields[i].kind {
                Kind::Switch => params.set(key.clone(), matches.get_flag(&key)),
                _ => match matches.get_one::<String>(&key) {
                    Some(value) => params.set(key.clone(), value.clone()),
                    None => continue,
                },
            };
        }
        let integrator = matches.get_one::<String>("integrator").cloned();
        Ok(IntegratorArgs {
            integrator: integrator.unwrap_or_else(|| DEFAULT.to_string()),
            params,
        })
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl clap::Args for IntegratorArgs {
    fn augment_args(cmd: Command) -> Command {
        let names: Vec<_> = registry().integrators().map(|e| e.name).collect();
        let mut cmd = cmd.arg(
            Arg::new("integrator")
                .long("integrator")
                .default_value(DEFAULT)
                .value_parser(PossibleValuesParser::new(names))
                .help("Integrator (`fenestra list` says what each does)"),
        );
        for (key, group, i) in flags() {
            let field = &group.fields[i];
            let heading = group.about.trim_end_matches('.').to_string();
            let default = match (&group.defaults[field.name], field.kind) {
                (serde_json::Value::Null | serde_json::Value::Bool(false), _) => String::new(),
                // As the parser takes it (a type may serialise a choice otherwise).
                (serde_json::Value::String(s), Kind::Choice(names)) => {
                    let name = names.iter().find(|n| n.eq_ignore_ascii_case(s));
                    format!(" [default: {}]", name.unwrap_or(&s.as_str()))
                }
                (serde_json::Value::String(s), _) => format!(" [default: {s}]"),
                (v, _) => format!(" [default: {v}]"),
            };
            let mut arg = Arg::new(key.clone())
                .long(group.flag(field))
                .value_name(field.name.to_uppercase())
                .help(format!("{} ({key}){default}", field.help))
                .help_heading(heading);
            arg = match (field.kind, registry().choices(&key)) {
                (_, Some(names)) => arg.value_parser(PossibleValuesParser::new(names)),
                (Kind::Switch, _) => arg.action(ArgAction::SetTrue),
                (Kind::Choice(names), _) => arg.value_parser(PossibleValuesParser::new(names)),
                (Kind::Value, _) => arg,
            };
            cmd = cmd.arg(arg);
        }
        cmd
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        args: IntegratorArgs,
    }

    fn parse(flags: &[&str]) -> Result<IntegratorArgs, clap::Error> {
        Cli::try_parse_from(std::iter::once("fenestra").chain(flags.iter().copied()))
            .map(|c| c.args)
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
        assert_eq!(args.integrator, "sdrc");
        let expected = Params::new()
            .with("sdrc.a", "0.3")
            .with("path.max_depth", "4");
        assert_eq!(args.params, expected);
        let args = parse(&["--portals", "auto", "--no-portal-cache"]).expect("flags");
        let expected = Params::new()
            .with("portals.source", "auto")
            .with("portals.no_cache", true);
        assert_eq!(args.params, expected);
        assert_eq!(parse(&[]).expect("no flags").params, Params::new());
    }

    #[test]
    fn every_option_has_a_flag_and_choices_are_checked_by_the_parser() {
        let mut seen = std::collections::HashSet::new();
        for (key, group, i) in flags() {
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
                .contains("possible values: power, uniform, all, bvh, learned"),
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
        let from_flags = settings(&flags.integrator, &flags.params);
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
            &parse(&["--integrator", "sdrc"]).expect("flags").params,
        );
        let sdrc = serde_json::to_value(fenestra_cache::SdrcOptions::default()).expect("json");
        assert_eq!(defaults["sdrc"], sdrc);
        assert_eq!(defaults["max_depth"], scene.defaults.max_depth);
    }

    #[test]
    fn errors_name_the_flag_and_the_key() {
        let e = OptionError::new("sdrc.a", "must be positive, got 0");
        assert_eq!(flag_error(&e), "--sdrc-a: sdrc.a must be positive, got 0");
        assert_eq!(flag_of("portals.source").as_deref(), Some("--portals"));
        assert_eq!(flag_of("path.max_depth").as_deref(), Some("--max-depth"));
    }
}
