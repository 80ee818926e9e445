//! The `fenestra` command line as a library: the subcommands with their flags, the flags
//! made from the integrator registry's option groups, progress and Ctrl-C. What a render is
//! (scenes, jobs, their files) is the session's (`fenestra-session`), which the Python module
//! stands on too: the command line parses, calls it and prints.

pub mod commands;
pub mod integrators;
pub mod support;

/// A session's error as the command line says it: settings and options named by their flags.
pub fn flagged(e: fenestra_session::Error) -> anyhow::Error {
    match e {
        fenestra_session::Error::Failed(e) => e,
        e => anyhow::anyhow!(e.worded(fenestra_session::Style::Flag)),
    }
}

/// A rayon pool with `threads` workers (all cores by default).
pub fn thread_pool(threads: Option<usize>) -> anyhow::Result<rayon::ThreadPool> {
    fenestra_session::thread_pool(threads).map_err(flagged)
}
