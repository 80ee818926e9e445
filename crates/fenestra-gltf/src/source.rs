//! A glTF file's JSON (checked so that reading it cannot panic) and its buffers: the GLB
//! binary chunk, `data:` URIs and external files beside it.

use crate::error::{pointer, GltfError};
use base64::Engine as _;
use gltf::json::validation::Validate;
use std::path::{Path, PathBuf};

/// A glTF document with its buffers' bytes.
pub struct Source {
    /// The .gltf or .glb file.
    pub path: PathBuf,
    /// Its JSON.
    pub document: gltf::Document,
    /// Each buffer's bytes, in order.
    pub buffers: Vec<Vec<u8>>,
    /// Every file read (the scene file first).
    pub files: Vec<PathBuf>,
}

impl Source {
    /// Reads `path` and every buffer it uses.
    pub fn open(path: &Path) -> Result<Source, GltfError> {
        let bytes =
            std::fs::read(path).map_err(|e| GltfError::file(path, format!("cannot read: {e}")))?;
        check_glb_header(path, &bytes)?;
        let gltf = gltf::Gltf::from_slice_without_validation(&bytes)
            .map_err(|e| GltfError::file(path, e.to_string()))?;
        check(path, &gltf.document)?;
        let mut source = Source {
            path: path.to_path_buf(),
            document: gltf.document,
            buffers: Vec::new(),
            files: vec![path.to_path_buf()],
        };
        let buffers: Vec<(usize, Option<String>, usize)> = source
            .document
            .buffers()
            .map(|b| {
                let uri = match b.source() {
                    gltf::buffer::Source::Bin => None,
                    gltf::buffer::Source::Uri(uri) => Some(uri.to_string()),
                };
                (b.index(), uri, b.length())
            })
            .collect();
        for (index, uri, length) in buffers {
            let at = format!("/buffers/{index}");
            let data = match uri {
                None => gltf.blob.clone().ok_or_else(|| {
                    GltfError::at(
                        path,
                        &at,
                        "refers to a GLB binary chunk the file does not have",
                    )
                })?,
                Some(uri) => source.read_uri(&uri, &at)?,
            };
            if data.len() < length {
                return Err(GltfError::at(
                    path,
                    &at,
                    format!(
                        "holds {} bytes but its byteLength is {} (truncated?)",
                        data.len(),
                        length
                    ),
                ));
            }
            source.buffers.push(data);
        }
        Ok(source)
    }

    /// The bytes a URI names: a base64 `data:` URI, or a file relative to the scene file.
    pub fn read_uri(&mut self, uri: &str, at: &str) -> Result<Vec<u8>, GltfError> {
        if let Some(rest) = uri.strip_prefix("data:") {
            let (_, data) = rest
                .split_once(";base64,")
                .ok_or_else(|| GltfError::at(&self.path, at, "a data: URI that is not base64"))?;
            return base64::engine::general_purpose::STANDARD
                .decode(data)
                .map_err(|e| GltfError::at(&self.path, at, format!("bad base64 data: {e}")));
        }
        if Path::new(&percent_decode(uri)).is_absolute() {
            return Err(GltfError::at(
                &self.path,
                at,
                format!(
                    "names the absolute path {uri}: glTF files name theirs relative to themselves"
                ),
            ));
        }
        let file = self.file_of(uri);
        // A device or a pipe (/dev/zero) would be read without end.
        match std::fs::metadata(&file) {
            Ok(m) if !m.is_file() => {
                return Err(GltfError::at(
                    &self.path,
                    at,
                    format!("{} is not a regular file", file.display()),
                ))
            }
            _ => {}
        }
        let bytes = std::fs::read(&file).map_err(|e| {
            GltfError::at(
                &self.path,
                at,
                format!("cannot read {}: {e}", file.display()),
            )
        })?;
        self.files.push(file);
        Ok(bytes)
    }

    /// The file a relative URI names (percent-escapes decoded).
    pub fn file_of(&self, uri: &str) -> PathBuf {
        let dir = self.path.parent().unwrap_or(Path::new("."));
        dir.join(percent_decode(uri))
    }
}

/// A GLB's declared total length must cover at least its 12-byte header (the `gltf` crate
/// subtracts the header from it unchecked: found by fuzzing) and no more than the file.
fn check_glb_header(path: &Path, bytes: &[u8]) -> Result<(), GltfError> {
    let Some(rest) = bytes.strip_prefix(b"glTF") else {
        return Ok(());
    };
    let declared = rest
        .get(4..8)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
    match declared {
        Some(n) if (12..=bytes.len()).contains(&n) => Ok(()),
        Some(n) => Err(GltfError::file(
            path,
            format!(
                "GLB header declares {n} bytes, the file has {} (truncated or corrupt)",
                bytes.len()
            ),
        )),
        None => Err(GltfError::file(path, "GLB header cut short")),
    }
}

/// gltf-json's checks (indices in range, required fields), which make reading it safe, except
/// the one on `extensionsRequired`: the loader reports the extensions it cannot honour itself.
fn check(path: &Path, document: &gltf::Document) -> Result<(), GltfError> {
    let root = document.as_json();
    // gltf-json's own check of POSITION's min and max indexes the accessors unchecked
    // (found by fuzzing): its index is checked first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let position = gltf::json::validation::Checked::Valid(gltf::Semantic::Positions);
            if let Some(i) = prim.attributes.get(&position) {
                if i.value() >= root.accessors.len() {
                    return Err(GltfError::at(
                        path,
                        format!("/meshes/{m}/primitives/{p}/attributes/POSITION"),
                        format!(
                            "accessor {} out of range ({} accessors)",
                            i.value(),
                            root.accessors.len()
                        ),
                    ));
                }
            }
        }
    }
    // ... and the gltf crate unwraps a camera's projection of its type.
    for (c, camera) in root.cameras.iter().enumerate() {
        use gltf::json::camera::Type;
        use gltf::json::validation::Checked;
        let missing = match camera.type_ {
            Checked::Valid(Type::Perspective) => {
                camera.perspective.is_none().then_some("perspective")
            }
            Checked::Valid(Type::Orthographic) => {
                camera.orthographic.is_none().then_some("orthographic")
            }
            Checked::Invalid => Some("type"),
        };
        if let Some(what) = missing {
            return Err(GltfError::at(
                path,
                format!("/cameras/{c}/{what}"),
                "required value missing",
            ));
        }
    }
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |at, error| {
        let at = at().to_string();
        if !at.starts_with("extensionsRequired") {
            errors.push((at, error));
        }
    });
    match errors.first() {
        None => Ok(()),
        Some((at, error)) => {
            let what = match error {
                gltf::json::validation::Error::IndexOutOfBounds => "index out of range",
                gltf::json::validation::Error::Invalid => "invalid value",
                gltf::json::validation::Error::Missing => "required value missing",
                gltf::json::validation::Error::Oversize => "size beyond this machine's limits",
                gltf::json::validation::Error::Unsupported => "not supported",
            };
            let more = match errors.len() {
                1 => String::new(),
                n => format!(" (and {} more problems)", n - 1),
            };
            Err(GltfError::at(path, pointer(at), format!("{what}{more}")))
        }
    }
}

/// `%20` and friends decoded; anything malformed kept as written.
fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match (
            bytes[i],
            bytes.get(i + 1).copied().and_then(hex),
            bytes.get(i + 2).copied().and_then(hex),
        ) {
            (b'%', Some(h), Some(l)) => {
                out.push((h * 16 + l) as u8);
                i += 3;
            }
            (b, _, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    #[test]
    fn percent_escapes_decode() {
        assert_eq!(super::percent_decode("my%20file%2B.bin"), "my file+.bin");
        assert_eq!(super::percent_decode("100%"), "100%");
    }
}
