//! What memory the process can still get, asked before allocating what a file or a request
//! declares (a film of a resolution, an image of the size its header claims): a clear refusal
//! instead of an abort when the allocation fails. Linux's figures: the machine's available
//! memory (`MemAvailable`) and, under `ulimit -v`, what the address-space limit leaves.

/// An allocation the process cannot get.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{what} needs {} of memory and {} can be had{}",
    gb(*.needed),
    gb(*.available),
    if *.limited { " (the process's address-space limit, ulimit -v)" } else { "" }
)]
pub struct OutOfMemory {
    /// What the memory is for ("a 30000x15000 image").
    pub what: String,
    /// Bytes asked.
    pub needed: u64,
    /// Bytes the process can get.
    pub available: u64,
    /// Whether the address-space limit, not the machine, is what leaves too little.
    pub limited: bool,
}

fn gb(bytes: u64) -> String {
    format!("{:.1} GB", bytes as f64 / 1e9)
}

/// Refuses `needed` bytes for `what` (named lazily) if the process cannot get them; accepts
/// where the figures cannot be read (not Linux).
pub fn ensure(needed: u64, what: impl FnOnce() -> String) -> Result<(), OutOfMemory> {
    let machine = meminfo_available();
    let process = address_space_left();
    let limited = matches!((machine, process), (Some(m), Some(p)) if p < m)
        || (machine.is_none() && process.is_some());
    match [machine, process].into_iter().flatten().min() {
        Some(available) if needed > available => Err(OutOfMemory {
            what: what(),
            needed,
            available,
            limited,
        }),
        _ => Ok(()),
    }
}

/// The machine's available memory (`MemAvailable` of /proc/meminfo), in bytes.
fn meminfo_available() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    kilobytes(&info, "MemAvailable:")
}

/// What the address-space limit leaves above the process's present size, in bytes; none
/// without a limit.
fn address_space_left() -> Option<u64> {
    let limits = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = limits
        .lines()
        .find(|l| l.starts_with("Max address space"))?;
    let soft: u64 = line
        .trim_start_matches("Max address space")
        .split_whitespace()
        .next()?
        .parse()
        .ok()?;
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let size = kilobytes(&status, "VmSize:")?;
    Some(soft.saturating_sub(size))
}

/// The value of a "Key:   N kB" line of a /proc file, in bytes.
fn kilobytes(text: &str, key: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(key))?;
    let kb: u64 = line[key.len()..].split_whitespace().next()?.parse().ok()?;
    Some(kb * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn what_the_machine_cannot_hold_is_refused_and_named() {
        assert!(ensure(1 << 20, || "a megabyte".into()).is_ok());
        let e = ensure(u64::MAX / 2, || "a 30000x15000 image".into()).expect_err("exabytes");
        assert!(e.available < u64::MAX / 2);
        let text = e.to_string();
        assert!(
            text.starts_with("a 30000x15000 image needs 9223372036.9 GB of memory and "),
            "{text}"
        );
    }

    #[test]
    fn proc_lines_read_as_bytes() {
        let status = "Name:\tx\nVmSize:\t  123456 kB\nVmRSS:\t 5 kB\n";
        assert_eq!(kilobytes(status, "VmSize:"), Some(123456 * 1024));
        assert_eq!(kilobytes(status, "VmPeak:"), None);
    }
}
