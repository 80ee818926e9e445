//! A parameter map: option keys (`group.field`) to values, as Mitsuba's `Properties`. Command
//! lines, bench files, scene files and Python all set options through one.

use serde_json::Value;
use std::collections::BTreeMap;

/// Option keys to values.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Params {
    values: BTreeMap<String, Value>,
}

impl Params {
    /// No options set: every one takes its default.
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets `key` (`group.field`) to `value`: a JSON value, or text to be read as the
    /// option's type reads it.
    pub fn set(&mut self, key: impl Into<String>, value: impl Into<Value>) -> &mut Self {
        self.values.insert(key.into(), value.into());
        self
    }

    /// As [`Params::set`], by value.
    pub fn with(mut self, key: impl Into<String>, value: impl Into<Value>) -> Self {
        self.set(key, value);
        self
    }

    /// Every key set, with its value, in key order.
    pub fn iter(&self) -> impl Iterator<Item = (&str, &Value)> {
        self.values.iter().map(|(k, v)| (k.as_str(), v))
    }

    /// The fields set in `group`, with their values.
    pub fn group<'a>(&'a self, group: &'a str) -> impl Iterator<Item = (&'a str, &'a Value)> {
        self.iter().filter_map(move |(key, value)| {
            let (g, field) = key.split_once('.')?;
            (g == group).then_some((field, value))
        })
    }

    /// Whether `key` is set.
    pub fn contains(&self, key: &str) -> bool {
        self.values.contains_key(key)
    }

    /// Whether no key is set.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }
}
