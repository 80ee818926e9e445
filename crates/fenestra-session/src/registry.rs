//! Every integrator and light sampler a session offers, assembled from the crates that bring
//! them (each has a `register()`), and the choice of one with its options.

use fenestra_render::options::Params;
use fenestra_render::registry::Registry;
use serde_json::{json, Value};
use std::sync::LazyLock;

/// Every integrator and light sampler of fenestra.
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

/// The integrator a render takes unless told.
pub const DEFAULT_INTEGRATOR: &str = "af_hf";

/// Which integrator, and the options given for it (options left out take their defaults).
#[derive(Clone, Debug)]
pub struct IntegratorChoice {
    /// The integrator's name (`fenestra list`).
    pub name: String,
    /// The options given, by key (`sdrc.a`).
    pub params: Params,
}

impl Default for IntegratorChoice {
    /// The default integrator with its defaults.
    fn default() -> Self {
        IntegratorChoice::named(DEFAULT_INTEGRATOR)
    }
}

impl IntegratorChoice {
    /// Integrator `name` with its defaults.
    pub fn named(name: &str) -> Self {
        IntegratorChoice {
            name: name.to_string(),
            params: Params::new(),
        }
    }

    /// The portals file given, if one was (not `auto`).
    pub fn portals_file(&self) -> Option<&str> {
        let given = self.params.iter().find(|(k, _)| *k == "portals.source");
        given.and_then(|(_, v)| v.as_str()).filter(|&p| p != "auto")
    }
}

/// Every integrator, light sampler and option, as JSON: `{"default_integrator", "integrators":
/// [{name, about, groups}], "light_samplers": [...], "options": [{key, keyword, flag, group,
/// help, default, choices}]}` (`groups`: the option groups each reads): what `fenestra list --json` prints and front ends (the Python
/// module, the Blender add-on) build their settings from.
pub fn catalogue() -> Value {
    let r = registry();
    let entries = |it: &mut dyn Iterator<Item = (&str, &str, &[&str])>| -> Vec<Value> {
        it.map(|(name, about, groups)| json!({"name": name, "about": about, "groups": groups}))
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
                    "flag": format!("--{}", g.flag(f)),
                    "group": g.about,
                    "help": f.help,
                    "default": g.defaults[f.name],
                    "choices": r.choices(&key),
                })
            })
        })
        .collect();
    json!({
        "default_integrator": DEFAULT_INTEGRATOR,
        "integrators": entries(&mut r.integrators().map(|e| (e.name, e.about, &e.groups[..]))),
        "light_samplers": entries(
            &mut r.light_samplers().map(|e| (e.name, e.about, &e.groups[..])),
        ),
        "options": options,
    })
}
