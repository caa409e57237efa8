//! How messages name the places of a glTF file: a node, a mesh or a
//! material by its name and index, so that an error says where to look.

pub(super) fn node_name(node: &gltf::Node) -> String {
    match node.name() {
        Some(n) if !n.is_empty() => format!("node `{n}` (index {})", node.index()),
        _ => format!("node {}", node.index()),
    }
}

pub(super) fn mesh_name(mesh: &gltf::Mesh) -> String {
    match mesh.name() {
        Some(n) if !n.is_empty() => format!("mesh `{n}` (index {})", mesh.index()),
        _ => format!("mesh {}", mesh.index()),
    }
}

/// The name a material goes by in messages: its name, else its index.
pub(super) fn material_label(mat: &gltf::Material) -> String {
    match (mat.name(), mat.index()) {
        (Some(n), _) if !n.is_empty() => n.to_string(),
        (_, Some(i)) => i.to_string(),
        (_, None) => "default".to_string(),
    }
}
