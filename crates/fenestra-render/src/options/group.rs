//! A group of options: one integrator's or one light sampler's settings as a plain type with
//! its defaults, documentation and validation in one place, set from a parameter map.

use super::error::OptionError;
use super::params::Params;
use super::value::{Kind, ValueError};
use serde_json::Value;

/// One option of a group, as documentation and command lines see it.
#[derive(Clone, Debug)]
pub struct Field {
    /// The field's name; the option's key is `group.name`.
    pub name: &'static str,
    /// What it does (the field's documentation).
    pub help: String,
    /// The command-line flag without dashes, when not `prefix-name`.
    pub flag: Option<&'static str>,
    /// How the command line takes it.
    pub kind: Kind,
}

/// A type of options: declared by [`options!`](crate::options!), which writes every
/// method but [`Validate::validate`].
pub trait Options: Default + Clone + serde::Serialize + Validate + Send + Sync + 'static {
    /// The group's name: keys are `GROUP.field`.
    const GROUP: &'static str;
    /// What command-line flags start with (`sdrc` gives `--sdrc-a`; empty: the field's name).
    const FLAG_PREFIX: &'static str;
    /// What the group is for (its documentation; a `--help` heading).
    fn about() -> String;

    /// The options, in declaration order.
    fn fields() -> Vec<Field>;

    /// Sets field `name` from `value`; the error says what the value should be.
    fn set(&mut self, name: &str, value: &Value) -> Result<(), ValueError>;

    /// The defaults overlaid with the keys of this group in `params`, validated.
    fn from_params(params: &Params) -> Result<Self, OptionError> {
        let mut options = Self::default();
        for (name, value) in params.group(Self::GROUP) {
            options
                .set(name, value)
                .map_err(|e| OptionError::new(format!("{}.{name}", Self::GROUP), e.0))?;
        }
        options.check()?;
        Ok(options)
    }

    /// [`Validate::validate`], with errors named by the option's key.
    fn check(&self) -> Result<(), OptionError> {
        self.validate().map_err(|e| e.in_group(Self::GROUP))
    }
}

/// What values a group of options accepts together. Errors name fields by their own name
/// (`OptionError::new("a", ..)`); the group's name is put before it.
pub trait Validate {
    /// Why the options cannot be used, if they cannot.
    fn validate(&self) -> Result<(), OptionError> {
        Ok(())
    }
}

/// Declares a type of options ([`Options`]): the struct, its `Default`, its serialisation
/// (the integrator's settings) and its fields' documentation, each default written once.
/// A `#[derive(..)]` after the documentation adds derives to `Clone, Debug, PartialEq`.
///
/// ```
/// fenestra_render::options! {
///     /// Options of the example integrator.
///     pub struct ExampleOptions in "example", flags "example" {
///         /// Rays per point.
///         pub rays: u32 = 16,
///         /// Switches the example off (`--no-example`, not `--example-off`).
///         pub off ["no-example"]: bool = false,
///     }
/// }
/// impl fenestra_render::options::Validate for ExampleOptions {}
/// ```
#[macro_export]
macro_rules! options {
    (
        $(#[doc = $doc:literal])*
        $(#[derive($($derive:ident),*)])?
        $vis:vis struct $name:ident in $group:literal, flags $prefix:literal {
            $(
                $(#[doc = $fdoc:literal])*
                $fvis:vis $field:ident $([$flag:literal])? : $ty:ty = $default:expr
            ),* $(,)?
        }
    ) => {
        $(#[doc = $doc])*
        #[derive(Clone, Debug, PartialEq $($(, $derive)*)?)]
        $vis struct $name {
            $( $(#[doc = $fdoc])* $fvis $field: $ty, )*
        }

        impl Default for $name {
            fn default() -> Self {
                $name { $( $field: $default, )* }
            }
        }

        impl $crate::options::serde::Serialize for $name {
            fn serialize<S: $crate::options::serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                use $crate::options::serde::ser::SerializeStruct;
                let mut out = s.serialize_struct(stringify!($name), [$(stringify!($field)),*].len())?;
                $( out.serialize_field(stringify!($field), &self.$field)?; )*
                out.end()
            }
        }

        impl $crate::options::Options for $name {
            const GROUP: &'static str = $group;
            const FLAG_PREFIX: &'static str = $prefix;
            fn about() -> String {
                $crate::options::help_text(&[$($doc),*])
            }

            fn fields() -> Vec<$crate::options::Field> {
                vec![$(
                    $crate::options::Field {
                        name: stringify!($field),
                        help: $crate::options::help_text(&[$($fdoc),*]),
                        flag: None $(.or(Some($flag)))?,
                        kind: <$ty as $crate::options::OptionValue>::KIND,
                    },
                )*]
            }

            fn set(
                &mut self,
                name: &str,
                value: &$crate::options::serde_json::Value,
            ) -> Result<(), $crate::options::ValueError> {
                match name {
                    $( stringify!($field) => {
                        self.$field = <$ty as $crate::options::OptionValue>::from_param(value)?;
                    } )*
                    _ => {
                        return Err($crate::options::ValueError(format!(
                            "is not an option of {}",
                            $group
                        )))
                    }
                }
                Ok(())
            }
        }
    };
}

/// A doc comment's lines as one paragraph.
pub fn help_text(lines: &[&str]) -> String {
    lines.iter().map(|l| l.trim()).collect::<Vec<_>>().join(" ")
}
