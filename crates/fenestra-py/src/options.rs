//! Integrator options as Python keyword arguments: each option's keyword is its command-line
//! flag with underscores (`--sdrc-a` is `sdrc_a`, key `sdrc.a`), so one name serves both and
//! every default, help text and check stays in the crate that declares the option.

use fenestra_cli::integrators::registry;
use fenestra_render::options::{OptionError, Params};
use pyo3::prelude::*;
use serde_json::{json, Value};

/// Every option: (key, keyword).
fn keywords() -> impl Iterator<Item = (String, String)> {
    registry().groups().iter().flat_map(|g| {
        g.fields.iter().map(move |f| {
            (
                format!("{}.{}", g.name, f.name),
                g.flag(f).replace('-', "_"),
            )
        })
    })
}

/// The keyword of option `key`.
fn keyword_of(key: &str) -> Option<String> {
    keywords().find(|(k, _)| k == key).map(|(_, w)| w)
}

/// An option's error as Python names it: by its keyword.
pub fn keyword_error(e: &OptionError) -> String {
    match keyword_of(&e.key) {
        Some(word) => format!("{word}: {e}"),
        None => e.to_string(),
    }
}

/// The parameters that `given` (a JSON object of keywords or `group.field` keys to values)
/// sets.
pub fn params(given: &str) -> anyhow::Result<Params> {
    let given: serde_json::Map<String, Value> = serde_json::from_str(given)?;
    let mut params = Params::new();
    for (name, value) in given {
        let key = match keywords().find(|(k, w)| *w == name || *k == name) {
            Some((key, _)) => key,
            None => anyhow::bail!(
                "{name}: no such option (fenestra.options() lists every option with its keyword)"
            ),
        };
        params.set(key, value);
    }
    Ok(params)
}

/// Every integrator, light sampler and option, as JSON: `{"integrators": [{name, about}],
/// "light_samplers": [...], "options": [{key, keyword, group, help, default, choices}]}`.
#[pyfunction]
pub fn options() -> String {
    let r = registry();
    let entries = |it: &mut dyn Iterator<Item = (&str, &str)>| -> Vec<Value> {
        it.map(|(name, about)| json!({"name": name, "about": about}))
            .collect()
    };
    let options: Vec<Value> = r
        .groups()
        .iter()
        .flat_map(|g| {
            g.fields.iter().map(move |f| {
                let key = format!("{}.{}", g.name, f.name);
                json!({
                    "key": key,
                    "keyword": g.flag(f).replace('-', "_"),
                    "group": g.about,
                    "help": f.help,
                    "default": g.defaults[f.name],
                    "choices": registry().choices(&key),
                })
            })
        })
        .collect();
    json!({
        "integrators": entries(&mut r.integrators().map(|e| (e.name, e.about))),
        "light_samplers": entries(&mut r.light_samplers().map(|e| (e.name, e.about))),
        "options": options,
    })
    .to_string()
}
