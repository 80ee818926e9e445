//! Integrators by name. The binary assembles a registry from the crates it links (render's
//! own path tracers, the research crates' integrators), each entry building its integrator
//! from the options the binary parsed; `O` is the binary's option type.

use crate::integrator::{Integrator, IntegratorError};

type Build<O> = dyn Fn(&O) -> Result<Box<dyn Integrator>, IntegratorError> + Send + Sync;

/// One registered integrator.
pub struct Entry<O: ?Sized> {
    /// The name it is asked for by (`--integrator NAME`).
    pub name: &'static str,
    /// One line on what it does.
    pub about: &'static str,
    build: Box<Build<O>>,
}

/// Integrators by name, built from options of type `O`.
pub struct Registry<O: ?Sized> {
    entries: Vec<Entry<O>>,
}

impl<O: ?Sized> Default for Registry<O> {
    fn default() -> Self {
        Registry {
            entries: Vec::new(),
        }
    }
}

impl<O: ?Sized> Registry<O> {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds an integrator; a later entry with the same name replaces the earlier one.
    pub fn register(
        mut self,
        name: &'static str,
        about: &'static str,
        build: impl Fn(&O) -> Result<Box<dyn Integrator>, IntegratorError> + Send + Sync + 'static,
    ) -> Self {
        self.entries.retain(|e| e.name != name);
        self.entries.push(Entry {
            name,
            about,
            build: Box::new(build),
        });
        self
    }

    /// The registered integrators, in registration order.
    pub fn entries(&self) -> &[Entry<O>] {
        &self.entries
    }

    /// Builds the integrator called `name` from `options`.
    pub fn build(&self, name: &str, options: &O) -> Result<Box<dyn Integrator>, IntegratorError> {
        match self.entries.iter().find(|e| e.name == name) {
            Some(e) => (e.build)(options),
            None => Err(IntegratorError::Unknown {
                name: name.to_string(),
                available: self
                    .entries
                    .iter()
                    .map(|e| e.name)
                    .collect::<Vec<_>>()
                    .join(", "),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::{hf, PathOptions};

    #[test]
    fn integrators_are_found_by_name_and_unknown_names_listed() {
        let registry = Registry::<u32>::new()
            .register("hf", "BSDF sampling", |&depth| {
                Ok(Box::new(hf(PathOptions {
                    max_depth: depth,
                    ..Default::default()
                })))
            })
            .register("broken", "never builds", |_| {
                Err(IntegratorError::Options("broken on purpose".into()))
            });
        let built = registry.build("hf", &4).expect("hf");
        assert_eq!(built.name(), "hf");
        assert_eq!(built.settings()["max_depth"], 4);
        let Err(e) = registry.build("bdpt", &4) else {
            panic!("built an unknown integrator");
        };
        assert_eq!(
            e.to_string(),
            "unknown integrator 'bdpt' (available: hf, broken)"
        );
        let Err(e) = registry.build("broken", &4) else {
            panic!("built a broken integrator");
        };
        assert_eq!(e.to_string(), "broken on purpose");
    }
}
