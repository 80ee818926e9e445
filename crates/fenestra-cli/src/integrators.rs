//! The integrators' command-line flags (and any options group's: `fenestra portals` makes
//! the estimator's the same way). Each crate registers its integrators and light
//! samplers with their option groups (the session assembles them); the flags are made from
//! those groups (`sdrc.a` is `--sdrc-a`), so an option's default, help and checks live only in
//! the crate that owns it.

use clap::builder::PossibleValuesParser;
use clap::parser::ValueSource;
use clap::{Arg, ArgAction, ArgMatches, Command};
use fenestra_render::options::{Kind, Params};
use fenestra_render::registry::Group;
use fenestra_session::{registry, IntegratorChoice, DEFAULT_INTEGRATOR};

/// Which integrator, and the options given for it on the command line.
#[derive(Clone, Debug)]
pub struct IntegratorArgs(pub IntegratorChoice);

/// Every option flag of `groups`: (key, group, field index).
fn flags(groups: &[Group]) -> impl Iterator<Item = (String, &Group, usize)> {
    groups.iter().flat_map(|g| {
        (0..g.fields.len()).map(move |i| (format!("{}.{}", g.name, g.fields[i].name), g, i))
    })
}

/// The options of `groups` given on the command line, by key.
pub fn params_given(matches: &ArgMatches, groups: &[Group]) -> Params {
    let mut params = Params::new();
    for (key, group, i) in flags(groups) {
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
    params
}

/// `cmd` with a flag for every option of `groups` (`sdrc.a` is `--sdrc-a`), under its
/// group's heading, with its help, default and choices.
pub fn with_flags(mut cmd: Command, groups: &[Group]) -> Command {
    for (key, group, i) in flags(groups) {
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

impl clap::FromArgMatches for IntegratorArgs {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let params = params_given(matches, registry().groups());
        let integrator = matches.get_one::<String>("integrator").cloned();
        Ok(IntegratorArgs(IntegratorChoice {
            name: integrator.unwrap_or_else(|| DEFAULT_INTEGRATOR.to_string()),
            params,
        }))
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl clap::Args for IntegratorArgs {
    fn augment_args(cmd: Command) -> Command {
        let names: Vec<_> = registry().integrators().map(|e| e.name).collect();
        let cmd = cmd.arg(
            Arg::new("integrator")
                .long("integrator")
                .default_value(DEFAULT_INTEGRATOR)
                .value_parser(PossibleValuesParser::new(names))
                .help("Integrator (`fenestra list` says what each does)"),
        );
        with_flags(cmd, registry().groups())
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

#[cfg(test)]
mod tests;
