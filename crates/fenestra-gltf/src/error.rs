//! What goes wrong reading a glTF file: always the file and, where there is one, the JSON
//! path of the object at fault (`/meshes/3/primitives/0/attributes/TEXCOORD_0`).

use std::path::{Path, PathBuf};

/// A glTF file that cannot be read as a scene.
#[derive(Debug, thiserror::Error)]
#[error("{}: {}{}", file.display(), pointer.as_deref().map(|p| format!("{p}: ")).unwrap_or_default(), message)]
pub struct GltfError {
    /// The .gltf or .glb file.
    pub file: PathBuf,
    /// The JSON pointer of the object at fault, if any.
    pub pointer: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl GltfError {
    /// An error about the whole file.
    pub fn file(file: &Path, message: impl Into<String>) -> Self {
        GltfError {
            file: file.to_path_buf(),
            pointer: None,
            message: message.into(),
        }
    }

    /// An error about the object at JSON pointer `pointer`.
    pub fn at(file: &Path, pointer: impl Into<String>, message: impl Into<String>) -> Self {
        GltfError {
            file: file.to_path_buf(),
            pointer: Some(pointer.into()),
            message: message.into(),
        }
    }
}

/// gltf-json's path (`meshes[3].primitives[0].attributes["TEXCOORD_0"]`) as a JSON pointer
/// (`/meshes/3/primitives/0/attributes/TEXCOORD_0`).
pub fn pointer(path: &str) -> String {
    let mut out = String::new();
    for part in path.split(['.', '[']) {
        let part = part.trim_end_matches(']').trim_matches('"');
        if !part.is_empty() {
            out.push('/');
            out.push_str(part);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn paths_become_json_pointers() {
        assert_eq!(
            super::pointer("meshes[3].primitives[0].attributes[\"TEXCOORD_0\"]"),
            "/meshes/3/primitives/0/attributes/TEXCOORD_0"
        );
        assert_eq!(super::pointer("scene"), "/scene");
    }
}
