//! The error of parsing a name from a fixed list (an integrator option, a sampling rule, a
//! backend): says what was given and what is accepted.

/// A name that is not one of the accepted ones.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown {what} '{given}' (expected {expected})")]
pub struct UnknownName {
    /// What kind of name it is ("light selection").
    pub what: &'static str,
    /// The name given.
    pub given: String,
    /// The accepted names, in words ("uniform or power").
    pub expected: &'static str,
}

impl UnknownName {
    /// `given` is not a `what`; `expected` lists the accepted names.
    pub fn new(what: &'static str, given: &str, expected: &'static str) -> Self {
        UnknownName {
            what,
            given: given.to_string(),
            expected,
        }
    }
}
