//! The `fenestra` front end as a library: the subcommands, the integrator registry with the
//! flags made from its option groups, scene arguments, progress and Ctrl-C. The `fenestra`
//! binary is its command line; the Python module renders through the same jobs, so an image
//! made from Python is the one the command line makes.

pub mod commands;
pub mod integrators;
pub mod support;

/// A rayon pool with `threads` workers (all cores by default).
pub fn thread_pool(threads: Option<usize>) -> anyhow::Result<rayon::ThreadPool> {
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(t) = threads {
        anyhow::ensure!(t > 0, "--threads must be at least 1");
        pool = pool.num_threads(t);
    }
    Ok(pool.build()?)
}
