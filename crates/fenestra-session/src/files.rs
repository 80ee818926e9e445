//! What a command reads and writes, checked before any work starts: no output may be one of
//! the command's inputs (a scene, a portals file, a reference, a texture the scene uses) or
//! another of its outputs, and no input may lie in a folder the command fills. Paths are
//! compared canonically (symbolic links and `..` resolved), so `./a/../scene.pbrt` is
//! `scene.pbrt`.

use anyhow::{bail, Context, Result};
use fenestra_render::{output, RenderStats};
use std::path::{Path, PathBuf};

/// Where a render's files go: OUT.exr, but an interrupted render never replaces a complete
/// one (its sidecar says it finished): it goes beside it, to OUT.interrupted.exr, with a note
/// saying so.
pub fn where_to_write(output: &Path, interrupted: bool) -> (PathBuf, Option<String>) {
    let (_, sidecar) = output::companion_paths(output);
    let complete = || {
        let text = std::fs::read_to_string(&sidecar).ok()?;
        let stats: RenderStats = serde_json::from_str(&text).ok()?;
        Some(!stats.interrupted)
    };
    if !interrupted || complete() != Some(true) {
        return (output.to_path_buf(), None);
    }
    let beside = interrupted_path(output);
    let note = format!(
        "{} holds a complete render: the interrupted one goes to {} beside it",
        output.display(),
        beside.display()
    );
    (beside, Some(note))
}

/// Where a render that must not replace the complete one at OUT.exr goes: OUT.interrupted.exr.
pub fn interrupted_path(output: &Path) -> PathBuf {
    output.with_extension("interrupted.exr")
}

/// Creates the folder an output file goes into, if it is missing.
pub fn create_output_folder(path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create output folder {}", dir.display()))?;
    }
    Ok(())
}

/// A command's inputs and outputs, each with what it is for.
#[derive(Clone, Default)]
pub struct Files {
    inputs: Vec<(PathBuf, String)>,
    outputs: Vec<(PathBuf, String)>,
    folders: Vec<(PathBuf, String)>,
}

/// `path` made absolute with links and `..` resolved; for a path that does not exist yet,
/// its folder's canonical path joined with its name.
fn canonical(path: &Path) -> PathBuf {
    if let Ok(p) = path.canonicalize() {
        return p;
    }
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    match (absolute.parent(), absolute.file_name()) {
        (Some(dir), Some(name)) => canonical(dir).join(name),
        _ => absolute,
    }
}

impl Files {
    /// A file the command reads.
    pub fn input(&mut self, path: &Path, what: &str) -> &mut Self {
        self.inputs.push((canonical(path), what.to_string()));
        self
    }

    /// Files the command reads.
    pub fn inputs(&mut self, paths: &[PathBuf], what: &str) -> &mut Self {
        for p in paths {
            self.input(p, what);
        }
        self
    }

    /// A file the command writes.
    pub fn output(&mut self, path: &Path, what: &str) -> &mut Self {
        self.outputs.push((canonical(path), what.to_string()));
        self
    }

    /// A folder the command writes files into.
    pub fn folder(&mut self, path: &Path, what: &str) -> &mut Self {
        self.folders.push((canonical(path), what.to_string()));
        self
    }

    /// Refuses outputs that are inputs or each other, inputs inside output folders, and
    /// outputs that cannot be written (a folder in the way, a missing or read-only folder):
    /// before the work, not after it.
    pub fn check(&self) -> Result<()> {
        for (i, (out, what)) in self.outputs.iter().enumerate() {
            if let Some((_, input)) = self.inputs.iter().find(|(p, _)| p == out) {
                bail!(
                    "{} ({what}) is also the {input} this command reads: refusing to overwrite it",
                    out.display()
                );
            }
            if let Some((_, other)) = self.outputs[..i].iter().find(|(p, _)| p == out) {
                bail!(
                    "{} would be written twice, as the {other} and as the {what}: give them different names",
                    out.display()
                );
            }
        }
        for (out, _) in &self.outputs {
            fenestra_core::fs::check_writable(out)?;
        }
        for (folder, what) in &self.folders {
            if folder.exists() && !folder.is_dir() {
                bail!("{} ({what}) is a file, not a folder", folder.display());
            }
            if let Some((p, input)) = self.inputs.iter().find(|(p, _)| p.starts_with(folder)) {
                bail!(
                    "{} ({input}) lies in {} ({what}), which this command writes into: choose another folder",
                    p.display(),
                    folder.display()
                );
            }
        }
        Ok(())
    }
}

/// Which of its optional files a render writes beside OUT.exr, OUT.png and OUT.json.
#[derive(Clone, Copy, Debug, Default)]
pub struct Beside {
    /// OUT.var.exr (and OUT.light-paths.exr and .png, where light paths are traced).
    pub variance: bool,
    /// OUT.film.
    pub state: bool,
    /// OUT.denoised.exr and OUT.denoised.png.
    pub denoised: bool,
    /// OUT.albedo.exr and OUT.normal.exr (the features as files of their own).
    pub feature_files: bool,
}

/// Adds the files a render writes for OUT.exr: OUT.png, OUT.json and those `beside` says.
pub fn render_outputs<'a>(files: &'a mut Files, exr: &Path, beside: Beside) -> &'a mut Files {
    let Beside {
        variance,
        state,
        denoised,
        feature_files,
    } = beside;
    let (png, json) = output::companion_paths(exr);
    files
        .output(exr, "image")
        .output(&png, "picture")
        .output(&json, "sidecar");
    if variance {
        let light_paths = output::light_paths_path(exr);
        files
            .output(&output::variance_path(exr), "variance image")
            .output(&light_paths, "light paths' image")
            .output(&light_paths.with_extension("png"), "light paths' picture");
    }
    if state {
        files.output(&output::film_state_path(exr), "film state");
    }
    if feature_files {
        let (albedo, normal) = output::feature_paths(exr);
        files
            .output(&albedo, "albedo image")
            .output(&normal, "normal image");
    }
    if denoised {
        let exr = output::denoised_path(exr);
        files
            .output(&exr, "denoised image")
            .output(&exr.with_extension("png"), "denoised picture");
    }
    files
}

/// Refuses a render's output that does not end in .exr; creates its folder.
pub fn check_exr(path: &Path) -> Result<()> {
    if path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
        != Some("exr")
    {
        bail!(
            "output {} must end in .exr (the PNG and JSON are written beside it)",
            path.display()
        );
    }
    create_output_folder(path)
}

/// The film-state file of a part of a split render given as its image (OUT.exr: OUT.film)
/// or as itself.
pub fn film_file_of(part: &Path) -> PathBuf {
    match part.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("exr") => output::film_state_path(part),
        _ => part.to_path_buf(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collisions_are_found_through_other_spellings() {
        let dir = std::env::temp_dir().join(format!("fenestra-files-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).expect("dir");
        let scene = dir.join("scene.pbrt");
        std::fs::write(&scene, "").expect("write");
        let mut f = Files::default();
        f.input(&scene, "scene")
            .output(&dir.join("sub/../out.exr"), "image");
        assert!(f.check().is_ok());
        f.output(&dir.join("sub/../scene.pbrt"), "export");
        let e = f.check().expect_err("overwrites the scene").to_string();
        assert!(e.contains("is also the scene"), "{e}");
        let mut f = Files::default();
        f.output(&dir.join("p.json"), "portals")
            .output(&dir.join("./p.json"), "picture");
        let e = f.check().expect_err("same output twice").to_string();
        assert!(
            e.contains("written twice, as the portals and as the picture"),
            "{e}"
        );
        let mut f = Files::default();
        f.input(&scene, "scene").folder(&dir, "report folder");
        let e = f.check().expect_err("input in output folder").to_string();
        assert!(e.contains("which this command writes into"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
