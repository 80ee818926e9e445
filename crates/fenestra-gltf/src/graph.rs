//! The node hierarchy: every node of the scene visited once with its world matrix. glTF
//! gives a node one parent at most; a node reached twice (a cycle, a second parent, a root
//! listed twice) is an error, so that no file can make the walk loop or multiply.

use crate::error::GltfError;
use crate::source::Source;
use glam::Mat4;

/// A node and its world matrix.
pub struct Placed<'a> {
    /// The node.
    pub node: gltf::Node<'a>,
    /// Its transform to world space.
    pub world: Mat4,
}

/// Every node of the file's scene (the default one, else the first, else every root node)
/// in depth-first order with its world matrix.
pub fn walk(src: &Source) -> Result<Vec<Placed<'_>>, GltfError> {
    let doc = &src.document;
    let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; doc.nodes().len()];
            doc.nodes()
                .flat_map(|n| n.children())
                .for_each(|c| is_child[c.index()] = true);
            doc.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    let mut seen = vec![false; doc.nodes().len()];
    let mut out = Vec::new();
    // An explicit stack: a hierarchy as deep as the file is long must not overflow ours.
    let mut todo: Vec<(gltf::Node, Mat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, Mat4::IDENTITY))
        .collect();
    while let Some((node, parent)) = todo.pop() {
        let at = format!("/nodes/{}", node.index());
        if std::mem::replace(&mut seen[node.index()], true) {
            return Err(GltfError::at(
                &src.path,
                at,
                "reached a second time: the node graph has a cycle, or the node a second parent (glTF allows one)",
            ));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if !world.is_finite() {
            return Err(GltfError::at(&src.path, at, "its transform is not finite"));
        }
        let children: Vec<gltf::Node> = node.children().collect();
        todo.extend(children.into_iter().rev().map(|c| (c, world)));
        out.push(Placed { node, world });
    }
    Ok(out)
}
