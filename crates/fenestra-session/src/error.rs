//! What a session refuses, typed so that each front end names the setting its own way: the
//! command line by its flag (`--sun-time`), Python by its keyword (`sun_time`). A setting's
//! keyword is its flag with underscores, and an integrator option's is its group's flag the
//! same way (`--sdrc-a`, `sdrc_a`), so one name serves both.

use crate::registry::registry;
use fenestra_render::options::OptionError;
use fenestra_render::registry::Group;

/// A setting of a render session, as its front ends name it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Setting {
    Spp,
    Time,
    Resolution,
    Samples,
    Crop,
    Threads,
    Camera,
    Environment,
    Sky,
    Sun,
    SunTime,
    Location,
    SunStrength,
}

impl Setting {
    /// Every setting.
    pub const ALL: [Setting; 13] = [
        Setting::Spp,
        Setting::Time,
        Setting::Resolution,
        Setting::Samples,
        Setting::Crop,
        Setting::Threads,
        Setting::Camera,
        Setting::Environment,
        Setting::Sky,
        Setting::Sun,
        Setting::SunTime,
        Setting::Location,
        Setting::SunStrength,
    ];

    /// Its Python keyword (`sun_time`).
    pub fn keyword(self) -> &'static str {
        match self {
            Setting::Spp => "spp",
            Setting::Time => "time",
            Setting::Resolution => "resolution",
            Setting::Samples => "samples",
            Setting::Crop => "crop",
            Setting::Threads => "threads",
            Setting::Camera => "camera",
            Setting::Environment => "environment",
            Setting::Sky => "sky",
            Setting::Sun => "sun",
            Setting::SunTime => "sun_time",
            Setting::Location => "location",
            Setting::SunStrength => "sun_strength",
        }
    }

    /// Its name in `style`.
    pub fn name(self, style: Style) -> String {
        match style {
            Style::Keyword => self.keyword().to_string(),
            Style::Flag => format!("--{}", self.keyword().replace('_', "-")),
        }
    }
}

/// How a front end names settings and options in its messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// Command-line flags: `--sun-time`, `--sdrc-a`.
    Flag,
    /// Keywords (Python): `sun_time`, `sdrc_a`.
    Keyword,
}

/// Why a session refused a request or failed.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A setting's value is refused: "{setting} {problem}" (no space before a problem that
    /// starts with a colon). The problem names other settings and options as `{keyword}`
    /// and `{group.field}`, worded as the front end names them.
    #[error("{}", self.worded(Style::Keyword))]
    Setting { setting: Setting, problem: String },
    /// An integrator option is refused.
    #[error("{}", self.worded(Style::Keyword))]
    Option(OptionError),
    /// Anything else: a scene file that does not read, an image that cannot be written.
    #[error(transparent)]
    Failed(#[from] anyhow::Error),
}

/// A session's result.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// `setting` is refused because of `problem` (which follows its name, and names other
    /// settings as `{keyword}`, options as `{group.field}`).
    pub fn setting(setting: Setting, problem: impl Into<String>) -> Self {
        Error::Setting {
            setting,
            problem: problem.into(),
        }
    }

    /// The message, with settings and options named in `style`.
    pub fn worded(&self, style: Style) -> String {
        match self {
            Error::Setting { setting, problem } => {
                let problem = with_names(problem, style);
                // "--sky: ..." where the problem starts with its colon.
                let gap = if problem.starts_with(':') { "" } else { " " };
                format!("{}{gap}{problem}", setting.name(style))
            }
            Error::Option(e) => match option_name(&e.key, style) {
                Some(name) => format!("{name}: {e}"),
                None => e.to_string(),
            },
            Error::Failed(e) => format!("{e:#}"),
        }
    }
}

/// `text` with each `{keyword}` of a setting and `{group.field}` of an option named in `style`
/// (anything else in braces stays as it is).
fn with_names(text: &str, style: Style) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(open) = rest.find(['{', '}']) {
        out.push_str(&rest[..open]);
        let after = &rest[open + 1..];
        // Text quoted by `literal`: a doubled brace stands for itself.
        if let Some(tail) = after.strip_prefix(&rest[open..open + 1]) {
            out.push_str(&rest[open..open + 1]);
            rest = tail;
            continue;
        }
        let close = after.find('}').filter(|_| rest.as_bytes()[open] == b'{');
        let Some(close) = close else {
            out.push_str(&rest[open..open + 1]);
            rest = after;
            continue;
        };
        let word = &after[..close];
        let named = Setting::ALL
            .iter()
            .find(|s| s.keyword() == word)
            .map(|s| s.name(style))
            .or_else(|| option_name(word, style));
        match named {
            Some(name) => out.push_str(&name),
            None => out.push_str(&rest[open..open + close + 2]),
        }
        rest = &after[close + 1..];
    }
    out.push_str(rest);
    out
}

/// `text` (a path, a user's value) to stand in a problem as it is: its braces doubled, so that
/// none is taken for a setting's name.
pub fn literal(text: &str) -> String {
    text.replace('{', "{{").replace('}', "}}")
}

/// The flag or keyword of integrator option `key` (`sdrc.a`), if the registry has it.
pub fn option_name(key: &str, style: Style) -> Option<String> {
    option_name_in(key, registry().groups(), style)
}

/// The flag or keyword of option `key` among `groups` (an options group outside the
/// registry's: the portal estimator's).
pub fn option_name_in(key: &str, groups: &[Group], style: Style) -> Option<String> {
    let (group, field) = key.split_once('.')?;
    let g = groups.iter().find(|g| g.name == group)?;
    let f = g.fields.iter().find(|f| f.name == field)?;
    Some(match style {
        Style::Flag => format!("--{}", g.flag(f)),
        Style::Keyword => g.flag(f).replace('-', "_"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_and_options_are_named_as_each_front_end_names_them() {
        let e = Error::setting(
            Setting::Samples,
            "0..2 says how many samples to take: not with {spp}; see {ias.threshold}, {nothing}, {",
        );
        assert_eq!(
            e.worded(Style::Flag),
            "--samples 0..2 says how many samples to take: not with --spp; see --ias-threshold, {nothing}, {"
        );
        assert_eq!(
            e.to_string(),
            "samples 0..2 says how many samples to take: not with spp; see ias_threshold, {nothing}, {"
        );
        let e = Error::setting(Setting::SunTime, ": at 0,0");
        assert_eq!(e.worded(Style::Flag), "--sun-time: at 0,0");
        // A path with braces in it stays as it is.
        let path = literal("/scenes/{spp}/{a.b} }{.exr");
        let e = Error::setting(
            Setting::Environment,
            format!("{path}: unreadable, see {{time}}"),
        );
        assert_eq!(
            e.worded(Style::Flag),
            "--environment /scenes/{spp}/{a.b} }{.exr: unreadable, see --time"
        );
    }
}
