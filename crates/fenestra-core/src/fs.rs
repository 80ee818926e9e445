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

/// Runs `write` on a temporary file beside `path` (same folder, so the rename cannot cross
/// file systems), then renames it into place. On failure the temporary file is removed and
/// whatever stood at `path` before is left as it was.
pub fn write_atomically<E: Display>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), E>,
) -> Result<(), WriteError> {
    let name = path
        .file_name()
        .ok_or_else(|| WriteError::new(path, "not a file name"))?
        .to_string_lossy()
        .into_owned();
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    // Keep the real extension last: image writers pick the format from it.
    let tmp = path.with_file_name(format!(".{name}.{}.tmp.{ext}", std::process::id()));
    if let Err(e) = write(&tmp) {
        let _ = std::fs::remove_file(&tmp);
        return Err(WriteError::new(path, e));
    }
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        WriteError::new(path, e)
    })
}

/// Writes `text` to `path` atomically.
pub fn write_text_atomically(path: &Path, text: &str) -> Result<(), WriteError> {
    write_atomically(path, |tmp| std::fs::write(tmp, text))
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
