//! The node hierarchy: every node of the scene visited with its world matrix (a node used
//! twice is placed twice; a cycle is an error, not a hang).

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
    let mut out = Vec::new();
    let mut stack: Vec<usize> = Vec::new();
    for root in roots {
        visit(src, root, Mat4::IDENTITY, &mut stack, &mut out)?;
    }
    Ok(out)
}

fn visit<'a>(
    src: &Source,
    node: gltf::Node<'a>,
    parent: Mat4,
    stack: &mut Vec<usize>,
    out: &mut Vec<Placed<'a>>,
) -> Result<(), GltfError> {
    if stack.contains(&node.index()) {
        let path: Vec<String> = stack.iter().map(|i| i.to_string()).collect();
        return Err(GltfError::at(
            &src.path,
            format!("/nodes/{}", node.index()),
            format!(
                "the node graph has a cycle (nodes {} -> {})",
                path.join(" -> "),
                node.index()
            ),
        ));
    }
    let local = Mat4::from_cols_array_2d(&node.transform().matrix());
    let world = parent * local;
    if !world.is_finite() {
        return Err(GltfError::at(
            &src.path,
            format!("/nodes/{}", node.index()),
            "its transform is not finite",
        ));
    }
    stack.push(node.index());
    out.push(Placed {
        node: node.clone(),
        world,
    });
    for child in node.children() {
        visit(src, child, world, stack, out)?;
    }
    stack.pop();
    Ok(())
}
