//! Integrators and light samplers by name, each built from a parameter map. Every crate that
//! brings integrators has a `register(&mut Registry)`; a program (the command line, the Python
//! module) assembles one registry from the crates it links and builds what it is asked for
//! from the options it was given, as keys (`sdrc.a`) of a [`Params`] map.

use crate::integrator::{IntegratorError, LightNextEvent, PathConfig, PathOptions};
use crate::light::LightOptions;
use crate::options::{Field, OptionError, Options, Params};
use crate::Integrator;
use fenestra_scene::SceneDesc;

type BuildIntegrator = dyn Fn(&Build) -> Result<Box<dyn Integrator>, IntegratorError> + Send + Sync;
type BuildLights = dyn Fn(&Build) -> Result<LightNextEvent, IntegratorError> + Send + Sync;

/// A group of options as the registry shows it (command lines, `fenestra list`).
#[derive(Clone, Debug)]
pub struct Group {
    /// Its name: keys are `name.field`.
    pub name: &'static str,
    /// What its command-line flags start with.
    pub flag_prefix: &'static str,
    /// What it is for.
    pub about: String,
    /// Its options.
    pub fields: Vec<Field>,
    /// Its defaults, serialised (a field's default is `defaults[field]`).
    pub defaults: serde_json::Value,
}

impl Group {
    /// The group of options type `O`.
    pub fn of<O: Options>() -> Self {
        Group {
            name: O::GROUP,
            flag_prefix: O::FLAG_PREFIX,
            about: O::about(),
            fields: O::fields(),
            // Through text, so that an f32 default reads as written (0.22, not 0.2199999988).
            defaults: serde_json::to_string(&O::default())
                .and_then(|text| serde_json::from_str(&text))
                .unwrap_or_default(),
        }
    }

    /// The command-line flag of `field` (without dashes).
    pub fn flag(&self, field: &Field) -> String {
        match (field.flag, self.flag_prefix) {
            (Some(flag), _) => flag.to_string(),
            (None, "") => field.name.replace('_', "-"),
            (None, prefix) => format!("{prefix}-{}", field.name.replace('_', "-")),
        }
    }
}

/// One registered integrator or light sampler.
pub struct Entry<B: ?Sized> {
    /// The name it is asked for by.
    pub name: &'static str,
    /// One line on what it does.
    pub about: &'static str,
    /// The groups of options it reads.
    pub groups: Vec<&'static str>,
    build: Box<B>,
}

/// What an integrator is built from: the options given and the scene it will render.
pub struct Build<'a> {
    /// The options given (keys `group.field`).
    pub params: &'a Params,
    /// The scene (its path length is the default; caches are keyed by its content).
    pub scene: &'a SceneDesc,
    registry: &'a Registry,
}

impl Build<'_> {
    /// The options of type `O`: their defaults overlaid with what was given, validated.
    pub fn options<O: Options>(&self) -> Result<O, OptionError> {
        O::from_params(self.params)
    }

    /// The path tracers' options, with the scene's path length unless one was given.
    pub fn path(&self) -> Result<PathOptions, OptionError> {
        Ok(self
            .options::<PathConfig>()?
            .resolve(self.scene.defaults.max_depth))
    }

    /// Light sampling by the light sampler `light.selection` names; `learns`: whether the
    /// integrator lets a sampler learn from its passes.
    pub fn next_event(
        &self,
        integrator: &str,
        learns: bool,
    ) -> Result<LightNextEvent, IntegratorError> {
        let selection = self.options::<LightOptions>()?.selection;
        let entry = self.registry.find_light_sampler(&selection)?;
        let next_event = (entry.build)(self)?;
        if next_event.learning() && !learns {
            return Err(OptionError::new(
                "light.selection",
                format!(
                    "{selection} learns from a render's passes, which {integrator} does not give it \
                     (it takes {})",
                    self.registry.light_sampler_names(false).join(", ")
                ),
            )
            .into());
        }
        Ok(next_event)
    }
}

/// Integrators and light samplers by name, with the options each reads.
#[derive(Default)]
pub struct Registry {
    groups: Vec<Group>,
    integrators: Vec<Entry<BuildIntegrator>>,
    light_samplers: Vec<(Entry<BuildLights>, bool)>,
}

impl Registry {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds integrator `name`, which reads the option groups `groups` (a later entry of the
    /// same name replaces the earlier one).
    pub fn integrator(
        &mut self,
        name: &'static str,
        about: &'static str,
        groups: Vec<Group>,
        build: impl Fn(&Build) -> Result<Box<dyn Integrator>, IntegratorError> + Send + Sync + 'static,
    ) -> &mut Self {
        let groups = self.add_groups(groups);
        self.integrators.retain(|e| e.name != name);
        self.integrators.push(Entry {
            name,
            about,
            groups,
            build: Box::new(build),
        });
        self
    }

    /// Adds light sampler `name` (a value of `light.selection`), which reads the option groups
    /// `groups`; `learns`: whether it learns from a render's passes.
    pub fn light_sampler(
        &mut self,
        name: &'static str,
        about: &'static str,
        groups: Vec<Group>,
        learns: bool,
        build: impl Fn(&Build) -> Result<LightNextEvent, IntegratorError> + Send + Sync + 'static,
    ) -> &mut Self {
        let groups = self.add_groups(groups);
        self.light_samplers.retain(|(e, _)| e.name != name);
        self.light_samplers.push((
            Entry {
                name,
                about,
                groups,
                build: Box::new(build),
            },
            learns,
        ));
        self
    }

    fn add_groups(&mut self, groups: Vec<Group>) -> Vec<&'static str> {
        let names = groups.iter().map(|g| g.name).collect();
        for group in groups {
            if !self.groups.iter().any(|g| g.name == group.name) {
                self.groups.push(group);
            }
        }
        names
    }

    /// The registered integrators, in registration order.
    pub fn integrators(&self) -> impl Iterator<Item = &Entry<BuildIntegrator>> {
        self.integrators.iter()
    }

    /// The registered light samplers, in registration order.
    pub fn light_samplers(&self) -> impl Iterator<Item = &Entry<BuildLights>> {
        self.light_samplers.iter().map(|(e, _)| e)
    }

    /// The names of the light samplers (those that do not learn unless `learning`).
    fn light_sampler_names(&self, learning: bool) -> Vec<&'static str> {
        let names = self
            .light_samplers
            .iter()
            .filter(|(_, learns)| learning || !learns);
        names.map(|(e, _)| e.name).collect()
    }

    /// Every group of options, in the order they were first registered.
    pub fn groups(&self) -> &[Group] {
        &self.groups
    }

    /// The values a key may take when they are the names of registered things
    /// (`light.selection`: the light samplers).
    pub fn choices(&self, key: &str) -> Option<Vec<&'static str>> {
        (key == "light.selection").then(|| self.light_sampler_names(true))
    }

    fn find_light_sampler(&self, name: &str) -> Result<&Entry<BuildLights>, OptionError> {
        self.light_samplers()
            .find(|e| e.name == name)
            .ok_or_else(|| {
                let known = self.light_sampler_names(true).join(", ");
                OptionError::new(
                    "light.selection",
                    format!("has no light sampler '{name}' (known: {known})"),
                )
            })
    }

    /// Builds integrator `name` from `params` to render `scene`. Every key must be an option
    /// the integrator reads (with its light sampler's, if it samples lights). The options the
    /// scene file sets (`RenderDefaults::options`) apply where the integrator reads them and
    /// `params` does not set them.
    pub fn build(
        &self,
        name: &str,
        params: &Params,
        scene: &SceneDesc,
    ) -> Result<Box<dyn Integrator>, IntegratorError> {
        let Some(entry) = self.integrators.iter().find(|e| e.name == name) else {
            return Err(IntegratorError::Unknown {
                name: name.to_string(),
                available: self
                    .integrators
                    .iter()
                    .map(|e| e.name)
                    .collect::<Vec<_>>()
                    .join(", "),
            });
        };
        let params = &scene_options(entry, params, scene);
        self.check_keys(entry, params)?;
        (entry.build)(&Build {
            params,
            scene,
            registry: self,
        })
    }

    /// Refuses keys that are no option, and options the integrator does not read.
    fn check_keys(
        &self,
        entry: &Entry<BuildIntegrator>,
        params: &Params,
    ) -> Result<(), OptionError> {
        let mut read = entry.groups.clone();
        if read.contains(&LightOptions::GROUP) {
            let selection = LightOptions::from_params(params)?.selection;
            read.extend(&self.find_light_sampler(&selection)?.groups);
        }
        for (key, _) in params.iter() {
            let (group, field) = key.split_once('.').unwrap_or((key, ""));
            let Some(g) = self.groups.iter().find(|g| g.name == group) else {
                let groups: Vec<_> = self.groups.iter().map(|g| g.name).collect();
                return Err(OptionError::new(
                    key,
                    format!("is not an option (the groups: {})", groups.join(", ")),
                ));
            };
            if !g.fields.iter().any(|f| f.name == field) {
                let fields: Vec<_> = g.fields.iter().map(|f| f.name).collect();
                return Err(OptionError::new(
                    key,
                    format!("is not an option ({group} has {})", fields.join(", ")),
                ));
            }
            if !read.contains(&group) {
                return Err(OptionError::new(
                    key,
                    format!(
                        "is not read by {} (it reads {})",
                        self.described(entry, params),
                        read.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The integrator's name, with its light sampler if it samples lights.
    fn described(&self, entry: &Entry<BuildIntegrator>, params: &Params) -> String {
        match LightOptions::from_params(params) {
            Ok(l) if entry.groups.contains(&LightOptions::GROUP) => {
                format!("{} with light.selection {}", entry.name, l.selection)
            }
            _ => entry.name.to_string(),
        }
    }
}

/// `params` with the options `scene` sets whose group `entry` reads and `params` leaves unset.
fn scene_options(entry: &Entry<BuildIntegrator>, params: &Params, scene: &SceneDesc) -> Params {
    let mut all = params.clone();
    for (key, value) in &scene.defaults.options {
        let group = key.split_once('.').map_or(key.as_str(), |(group, _)| group);
        if entry.groups.contains(&group) && !params.contains(key) {
            all.set(key.clone(), value.clone());
        }
    }
    all
}
