//! What an option's value can be, and how it is read from a parameter: a JSON value as a
//! bench file, Python or a scene file give it, or text as a command line gives it.

use serde_json::Value;
use std::path::PathBuf;

/// How the command line takes an option.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A value after the flag.
    Value,
    /// A flag alone, which sets `true`.
    Switch,
    /// One of these names after the flag.
    Choice(&'static [&'static str]),
}

/// Why a value does not fit an option: what it takes and what it got (the option's key is
/// put before it where the value is set).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct ValueError(pub String);

/// A type an option can hold.
pub trait OptionValue: Sized {
    /// How the command line takes it.
    const KIND: Kind = Kind::Value;

    /// The value of `param`, or why it is not one (without the option's name).
    fn from_param(param: &Value) -> Result<Self, ValueError>;
}

/// Numbers: from JSON numbers, or from text.
macro_rules! number {
    ($($t:ty: $what:literal),*) => {$(
        impl OptionValue for $t {
            fn from_param(param: &Value) -> Result<Self, ValueError> {
                let parsed = match param {
                    Value::String(s) => s.trim().parse::<$t>().ok(),
                    v => serde_json::from_value::<$t>(v.clone()).ok(),
                };
                parsed.ok_or_else(|| ValueError(format!("takes {}, got {param}", $what)))
            }
        }
    )*};
}

number!(f32: "a number", f64: "a number", u32: "a whole number from 0", u64: "a whole number from 0", usize: "a whole number from 0");

impl OptionValue for bool {
    const KIND: Kind = Kind::Switch;

    fn from_param(param: &Value) -> Result<Self, ValueError> {
        match param {
            Value::Bool(b) => Ok(*b),
            Value::String(s) if s == "true" => Ok(true),
            Value::String(s) if s == "false" => Ok(false),
            _ => Err(ValueError(format!("takes true or false, got {param}"))),
        }
    }
}

impl OptionValue for String {
    fn from_param(param: &Value) -> Result<Self, ValueError> {
        match param {
            Value::String(s) => Ok(s.clone()),
            _ => Err(ValueError(format!("takes text, got {param}"))),
        }
    }
}

impl OptionValue for PathBuf {
    fn from_param(param: &Value) -> Result<Self, ValueError> {
        String::from_param(param).map(PathBuf::from)
    }
}

/// Optional values: JSON null is none.
impl<T: OptionValue> OptionValue for Option<T> {
    const KIND: Kind = T::KIND;

    fn from_param(param: &Value) -> Result<Self, ValueError> {
        match param {
            Value::Null => Ok(None),
            v => T::from_param(v).map(Some),
        }
    }
}

/// Declares an enum whose values are named choices: an option value ([`OptionValue`]),
/// serialised, parsed (`FromStr`) and shown (`Display`) by its names.
#[macro_export]
macro_rules! choices {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident {
            $( $(#[doc = $doc:literal])* $variant:ident = $text:literal ),+ $(,)?
        }
    ) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        $vis enum $name {
            $( $(#[doc = $doc])* $variant, )+
        }

        impl $name {
            /// Every name, in declaration order.
            pub const NAMES: &'static [&'static str] = &[$($text),+];

            /// The value's name.
            pub fn as_str(self) -> &'static str {
                match self { $( $name::$variant => $text, )+ }
            }
        }

        impl ::std::str::FromStr for $name {
            type Err = $crate::options::ValueError;
            fn from_str(s: &str) -> Result<Self, $crate::options::ValueError> {
                match s {
                    $( $text => Ok($name::$variant), )+
                    _ => Err($crate::options::ValueError(format!(
                        "takes one of {}, got '{s}'",
                        Self::NAMES.join(", ")
                    ))),
                }
            }
        }

        impl ::std::fmt::Display for $name {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str(self.as_str())
            }
        }

        impl $crate::options::serde::Serialize for $name {
            fn serialize<S: $crate::options::serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(self.as_str())
            }
        }

        impl $crate::options::OptionValue for $name {
            const KIND: $crate::options::Kind = $crate::options::Kind::Choice(Self::NAMES);

            fn from_param(
                param: &$crate::options::serde_json::Value,
            ) -> Result<Self, $crate::options::ValueError> {
                match param {
                    $crate::options::serde_json::Value::String(s) => s.parse(),
                    v => Err($crate::options::ValueError(format!(
                        "takes one of {}, got {v}",
                        Self::NAMES.join(", ")
                    ))),
                }
            }
        }
    };
}
