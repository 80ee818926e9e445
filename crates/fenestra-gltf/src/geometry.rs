//! Mesh primitives as triangle meshes: attributes read once per primitive, triangle strips
//! and fans unrolled, then placed in the world once per node that uses them.

use crate::accessor;
use crate::error::GltfError;
use crate::report::Report;
use crate::source::Source;
use fenestra_core::{Vec2, Vec3};
use fenestra_scene::TriangleMesh;
use glam::{Mat3, Mat4};
use gltf::mesh::Mode;
use gltf::Semantic;

/// A primitive in its mesh's own frame (uv already flipped to fenestra's convention).
pub struct LocalMesh {
    /// Its triangles.
    pub mesh: TriangleMesh,
    /// The glTF material it names, if any.
    pub material: Option<usize>,
}

/// Reads primitive `p` of mesh `mesh`; `None` (said in the report) for points and lines.
pub fn primitive(
    src: &Source,
    mesh: usize,
    p: &gltf::Primitive,
    report: &mut Report,
) -> Result<Option<LocalMesh>, GltfError> {
    let at = format!("/meshes/{mesh}/primitives/{}", p.index());
    if !matches!(
        p.mode(),
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        report.say(&at, format!("{:?} primitives are not rendered", p.mode()));
        return Ok(None);
    }
    let Some(positions) = p.get(&Semantic::Positions) else {
        return Err(GltfError::at(
            &src.path,
            format!("{at}/attributes"),
            "no POSITION attribute",
        ));
    };
    let positions: Vec<Vec3> = accessor::floats::<3>(src, &positions)?
        .into_iter()
        .map(Vec3::from)
        .collect();
    let n = positions.len();
    let normals = per_vertex(src, p, (Semantic::Normals, &at, "NORMAL"), n, Vec3::from)?;
    // fenestra's v runs up the image, glTF's down.
    let uvs = per_vertex(
        src,
        p,
        (Semantic::TexCoords(0), &at, "TEXCOORD_0"),
        n,
        |[u, v]| Vec2::new(u, 1.0 - v),
    )?;
    if p.get(&Semantic::Colors(0)).is_some() {
        report.say(
            format!("{at}/attributes/COLOR_0"),
            "vertex colours are not supported (ignored)",
        );
    }
    if p.get(&Semantic::Tangents).is_some() {
        report.say(
            format!("{at}/attributes/TANGENT"),
            "tangents are not read (normal maps use each triangle's uv frame)",
        );
    }
    if p.morph_targets().next().is_some() {
        report.say(
            format!("{at}/targets"),
            "morph targets are not applied (the base shape is used)",
        );
    }
    let order: Vec<u32> = match p.indices() {
        Some(a) => accessor::indices(src, &a)?,
        None => (0..n as u32).collect(),
    };
    if let Some(&bad) = order.iter().find(|&&i| i as usize >= n) {
        return Err(GltfError::at(
            &src.path,
            format!("{at}/indices"),
            format!("vertex index {bad} out of range ({n} vertices)"),
        ));
    }
    let indices = triangles(p.mode(), &order);
    Ok(Some(LocalMesh {
        mesh: TriangleMesh {
            positions,
            normals,
            uvs,
            indices,
        },
        material: p.material().index(),
    }))
}

/// Attribute `semantic` of primitive `p` (at JSON path `at`/attributes/`name`), if it has
/// it: `N` floats per vertex mapped by `f`, one for each of the `n` vertices.
fn per_vertex<const N: usize, T>(
    src: &Source,
    p: &gltf::Primitive,
    (semantic, at, name): (Semantic, &str, &str),
    n: usize,
    f: impl Fn([f32; N]) -> T,
) -> Result<Option<Vec<T>>, GltfError> {
    let Some(a) = p.get(&semantic) else {
        return Ok(None);
    };
    let values: Vec<T> = accessor::floats::<N>(src, &a)?.into_iter().map(f).collect();
    if values.len() != n {
        return Err(GltfError::at(
            &src.path,
            format!("{at}/attributes/{name}"),
            format!("{} values for {n} vertices", values.len()),
        ));
    }
    Ok(Some(values))
}

/// Triangles of a list, strip or fan of vertex indices (degenerate ones dropped).
fn triangles(mode: Mode, v: &[u32]) -> Vec<[u32; 3]> {
    let tris: Vec<[u32; 3]> = match mode {
        Mode::TriangleStrip => (2..v.len())
            .map(|i| match i % 2 {
                0 => [v[i - 2], v[i - 1], v[i]],
                _ => [v[i - 1], v[i - 2], v[i]],
            })
            .collect(),
        Mode::TriangleFan => (2..v.len()).map(|i| [v[0], v[i - 1], v[i]]).collect(),
        _ => v.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
    };
    tris.into_iter()
        .filter(|[a, b, c]| a != b && b != c && a != c)
        .collect()
}

/// `local` placed by the node's world matrix: positions moved, normals by the inverse
/// transpose, and the winding reversed under a mirroring transform so that the front stays
/// the front.
pub fn placed(local: &TriangleMesh, world: &Mat4) -> TriangleMesh {
    let normal_matrix = Mat3::from_mat4(*world).inverse().transpose();
    let mirrored = world.determinant() < 0.0;
    TriangleMesh {
        positions: local
            .positions
            .iter()
            .map(|p| world.transform_point3(*p))
            .collect(),
        normals: local.normals.as_ref().map(|n| {
            n.iter()
                .map(|v| (normal_matrix * *v).normalize_or_zero())
                .collect()
        }),
        uvs: local.uvs.clone(),
        indices: match mirrored {
            true => local.indices.iter().map(|&[a, b, c]| [a, c, b]).collect(),
            false => local.indices.clone(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_unroll_with_consistent_winding() {
        assert_eq!(
            triangles(Mode::TriangleStrip, &[0, 1, 2, 3]),
            vec![[0, 1, 2], [2, 1, 3]]
        );
        assert_eq!(
            triangles(Mode::TriangleFan, &[0, 1, 2, 3]),
            vec![[0, 1, 2], [0, 2, 3]]
        );
        assert_eq!(
            triangles(Mode::Triangles, &[0, 1, 2, 3, 3, 4]),
            vec![[0, 1, 2]]
        );
    }
}
