//! What a glTF file asks for that fenestra does not do, or does its own documented way: each
//! said once, with the JSON pointer of its first occurrence and how often it occurs.

use std::collections::BTreeMap;

/// Messages and where they first occurred, in the order first seen.
#[derive(Default)]
pub struct Report {
    seen: BTreeMap<String, (usize, String, usize)>,
}

impl Report {
    /// Records `what` at JSON pointer `at`.
    pub fn say(&mut self, at: impl Into<String>, what: impl Into<String>) {
        let n = self.seen.len();
        let entry = self.seen.entry(what.into()).or_insert((n, at.into(), 0));
        entry.2 += 1;
    }

    /// One line per message: "`at`: what (n times)".
    pub fn lines(&self) -> Vec<String> {
        let mut v: Vec<_> = self.seen.iter().collect();
        v.sort_by_key(|(_, (order, ..))| *order);
        v.into_iter()
            .map(|(what, (_, at, n))| match n {
                1 => format!("{at}: {what}"),
                n => format!("{at}: {what} ({n} times)"),
            })
            .collect()
    }
}
