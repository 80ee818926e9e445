//! Integrator options as Python keyword arguments: each option's keyword is its command-line
//! flag with underscores (`--sdrc-a` is `sdrc_a`, key `sdrc.a`), so one name serves both and
//! every default, help text and check stays in the crate that declares the option.

use fenestra_render::options::Params;
use fenestra_render::registry::Group;
use pyo3::prelude::*;
use serde_json::Value;

/// The parameters that `given` (a JSON object of keywords or `group.field` keys to values)
/// sets, among the options of `groups`.
pub fn params(given: &str, groups: &[Group]) -> anyhow::Result<Params> {
    let given: serde_json::Map<String, Value> = serde_json::from_str(given)?;
    let mut params = Params::new();
    for (name, value) in given {
        let key = groups.iter().find_map(|g| {
            g.fields.iter().find_map(|f| {
                let key = format!("{}.{}", g.name, f.name);
                (g.flag(f).replace('-', "_") == name || key == name).then_some(key)
            })
        });
        let Some(key) = key else {
            anyhow::bail!(
                "{name}: no such option (fenestra.options() lists every option with its keyword)"
            );
        };
        params.set(key, value);
    }
    Ok(params)
}

/// Every integrator, light sampler and option, as JSON: what `fenestra list --json` prints
/// but the built-in scenes (`fenestra_session::catalogue`).
#[pyfunction]
pub fn options() -> String {
    fenestra_session::catalogue().to_string()
}
