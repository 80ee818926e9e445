//! Writing files so that an interrupted write never leaves a truncated file under the final
//! name: every output of fenestra (images, sidecars, portals, exports, matrices) goes through
//! [`write_atomically`].

use std::fmt::Display;
use std::path::{Path, PathBuf};

/// A file that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {path}: {reason}")]
pub struct WriteError {
    /// The file's final name.
    pub path: PathBuf,
    /// What went wrong.
    pub reason: String,
}

impl WriteError {
    /// The error for `path` with `reason`.
    pub fn new(path: &Path, reason: impl Display) -> Self {
        WriteError {
            path: path.to_path_buf(),
            reason: reason.to_string(),
        }
    }
}

/// Files written as one set: each goes to a temporary file beside its final name (same
/// folder, so renames cannot cross file systems), and only once all are written are they
/// renamed into place. A failure or an interruption while writing leaves every old file of
/// the set as it was; temporaries of a set dropped before `commit` are removed, and those left
/// by a killed process are removed by the next write to the same name.
#[derive(Default)]
pub struct FileSet {
    /// (temporary, final name), in the order staged.
    staged: Vec<(PathBuf, PathBuf)>,
}

impl FileSet {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Writes one file of the set: `write` gets the temporary path.
    pub fn stage<E: Display>(
        &mut self,
        path: &Path,
        write: impl FnOnce(&Path) -> Result<(), E>,
    ) -> Result<(), WriteError> {
        let tmp = temporary(path)?;
        self.staged.push((tmp.clone(), path.to_path_buf()));
        write(&tmp).map_err(|e| WriteError::new(path, e))
    }

    /// Renames every staged file into place.
    pub fn commit(mut self) -> Result<(), WriteError> {
        for (tmp, path) in std::mem::take(&mut self.staged) {
            std::fs::rename(&tmp, &path).map_err(|e| {
                let _ = std::fs::remove_file(&tmp);
                WriteError::new(&path, e)
            })?;
        }
        Ok(())
    }
}

impl Drop for FileSet {
    fn drop(&mut self) {
        for (tmp, _) in &self.staged {
            let _ = std::fs::remove_file(tmp);
        }
    }
}

/// The temporary name of `path` for this process, `.NAME.PID.tmp.EXT` (the real extension
/// last: image writers pick the format from it). Temporaries of the same name left by
/// processes that no longer run are removed on the way.
fn temporary(path: &Path) -> Result<PathBuf, WriteError> {
    let name = path
        .file_name()
        .ok_or_else(|| WriteError::new(path, "not a file name"))?
        .to_string_lossy()
        .into_owned();
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    remove_stale_temporaries(path, &name);
    Ok(path.with_file_name(format!(".{name}.{}.tmp.{ext}", std::process::id())))
}

/// Removes `.NAME.PID.tmp.*` beside `path` whose process is gone (where the system says so:
/// /proc on Linux).
fn remove_stale_temporaries(path: &Path, name: &str) {
    let proc = Path::new("/proc");
    if !proc.is_dir() {
        return;
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let prefix = format!(".{name}.");
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let Some(rest) = file.strip_prefix(&prefix) else {
            continue;
        };
        let Some((pid, tail)) = rest.split_once('.') else {
            continue;
        };
        let gone = pid
            .parse::<u32>()
            .is_ok_and(|p| p != std::process::id() && !proc.join(pid).exists());
        if tail.starts_with("tmp.") && gone {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Runs `write` on a temporary file beside `path`, then renames it into place: an
/// interrupted write never leaves a truncated file under the final name.
pub fn write_atomically<E: Display>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), E>,
) -> Result<(), WriteError> {
    let mut set = FileSet::new();
    set.stage(path, write)?;
    set.commit()
}

/// Whether `path` can be written, checked before long work rather than after it: it is not a
/// folder, and a file can be created in its folder (which must exist).
pub fn check_writable(path: &Path) -> Result<(), WriteError> {
    if path.is_dir() {
        return Err(WriteError::new(path, "it is a folder"));
    }
    let probe = temporary(path)?.with_extension("probe");
    std::fs::write(&probe, b"").map_err(|e| WriteError::new(path, e))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// Writes `text` to `path` atomically.
pub fn write_text_atomically(path: &Path, text: &str) -> Result<(), WriteError> {
    write_atomically(path, |tmp| std::fs::write(tmp, text))
}

/// A name made safe for file names: lower case, `builtin:` dropped, anything but letters,
/// digits, '-' and '.' replaced by '_'.
pub fn slug(s: &str) -> String {
    let mut s = s.strip_prefix("builtin:").unwrap_or(s);
    // A scene beside the repository ("../../shared/scenes/...") is named by what follows.
    while let Some(rest) = s.strip_prefix("../").or_else(|| s.strip_prefix("./")) {
        s = rest;
    }
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '.' {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slugs_name_scenes_by_what_sets_them_apart() {
        assert_eq!(slug("builtin:box-hole"), "box-hole");
        assert_eq!(
            slug("../../shared/scenes/gltf/Breakfast Room.gltf"),
            "shared_scenes_gltf_breakfast_room.gltf"
        );
        assert_eq!(slug("./a/b.pbrt"), "a_b.pbrt");
    }

    #[test]
    fn a_failed_write_keeps_the_old_file_and_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("fenestra-fs-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("a.txt");
        write_text_atomically(&path, "first").expect("write");
        let e = write_atomically(&path, |tmp| {
            std::fs::write(tmp, "half")?;
            Err(std::io::Error::other("disk full"))
        })
        .expect_err("the write fails");
        assert!(e.to_string().contains("a.txt: disk full"), "{e}");
        assert_eq!(std::fs::read_to_string(&path).expect("read"), "first");
        let left: Vec<_> = std::fs::read_dir(&dir).expect("dir").collect();
        assert_eq!(left.len(), 1, "only a.txt remains");
        write_text_atomically(&path, "second").expect("write");
        assert_eq!(std::fs::read_to_string(&path).expect("read"), "second");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_set_is_replaced_whole_or_not_at_all() {
        let dir = std::env::temp_dir().join(format!("fenestra-set-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let (a, b) = (dir.join("a.txt"), dir.join("b.txt"));
        write_text_atomically(&a, "old a").expect("write");
        write_text_atomically(&b, "old b").expect("write");
        // The second file fails: the first keeps its old content.
        let mut set = FileSet::new();
        set.stage(&a, |t| std::fs::write(t, "new a"))
            .expect("stage");
        assert!(set
            .stage(&b, |_| Err::<(), _>(std::io::Error::other("blocked")))
            .is_err());
        drop(set);
        assert_eq!(std::fs::read_to_string(&a).expect("read"), "old a");
        assert_eq!(
            std::fs::read_dir(&dir).expect("dir").count(),
            2,
            "no temporaries left"
        );
        // A temporary left by a process that no longer runs is removed by the next write.
        let stale = dir.join(".a.txt.4000000000.tmp.txt");
        std::fs::write(&stale, "half").expect("write");
        write_text_atomically(&a, "newer a").expect("write");
        if Path::new("/proc").is_dir() {
            assert!(!stale.exists(), "stale temporary removed");
        }
        // A folder where a file should go, or a missing folder, is found before any work.
        assert!(check_writable(&dir).is_err());
        assert!(check_writable(&dir.join("missing/x.exr")).is_err());
        assert!(check_writable(&dir.join("x.exr")).is_ok());
        assert_eq!(
            std::fs::read_dir(&dir).expect("dir").count(),
            2,
            "the probe is gone"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
