//! Mesh files: PLY (ply-rs-bw) and OBJ with MTL (tobj).

pub mod obj;
pub mod ply;

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
#[error("{path}: {reason}")]
pub struct MeshError {
    pub path: PathBuf,
    pub reason: String,
}

/// Fan triangulation of a polygon's vertex indices (PLY faces may be quads or n-gons).
fn fan(poly: &[u32], out: &mut Vec<[u32; 3]>) {
    for i in 1..poly.len().saturating_sub(1) {
        out.push([poly[0], poly[i], poly[i + 1]]);
    }
}
