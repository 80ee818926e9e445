//! Ctrl-C (and SIGTERM, as a job scheduler sends it) for long commands: the first asks the
//! work to stop and keep what it has (the command says what it will do with it); a second one
//! quits at once.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Installs the handler and returns the flag it sets. `then` says what happens to the work
/// done so far ("writing the samples taken so far").
pub fn on_ctrl_c(then: &'static str) -> Arc<AtomicBool> {
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    // Only the first handler of a process can be installed; every command installs one.
    let _ = ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
        eprintln!("\ninterrupted: {then} (Ctrl-C again to quit at once)");
    });
    cancel
}
