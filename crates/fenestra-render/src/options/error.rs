//! Errors of options, named by their keys, and the checks most options need.

/// An option with a value it cannot take, named by its key.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{key} {message}")]
pub struct OptionError {
    /// The option's key (`sdrc.a`); inside [`Validate::validate`], the field's name.
    pub key: String,
    /// What is wrong, after the key: "must be positive, got -1".
    pub message: String,
}

impl OptionError {
    /// `key` is wrong as `message` says.
    pub fn new(key: impl Into<String>, message: impl Into<String>) -> Self {
        OptionError {
            key: key.into(),
            message: message.into(),
        }
    }

    /// The error with its field's group put before the field's name.
    pub fn in_group(self, group: &str) -> Self {
        OptionError {
            key: format!("{group}.{}", self.key),
            ..self
        }
    }
}

/// `Ok` if `value` is a finite number above zero.
pub fn positive(name: &str, value: f32) -> Result<(), OptionError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(OptionError::new(
            name,
            format!("must be positive, got {value}"),
        ))
    }
}

/// `Ok` if `value` is a finite number from zero up.
pub fn non_negative(name: &str, value: f32) -> Result<(), OptionError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(OptionError::new(
            name,
            format!("must be 0 or more, got {value}"),
        ))
    }
}

/// `Ok` if `value` is at least 1.
pub fn at_least_one(name: &str, value: u64) -> Result<(), OptionError> {
    if value >= 1 {
        Ok(())
    } else {
        Err(OptionError::new(name, "must be at least 1"))
    }
}
