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
        fenestra_render::register(&mut registry);
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
pub const DEFAULT: &str = "af_hf";

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
mod tests;
