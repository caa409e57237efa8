//! The GPU's tree over a big mesh, kept in the cache folder (`bvh/`) and
//! keyed by the triangles it was built over: the build is the largest fixed
//! cost of ray tracing a scanned mesh (70 ms for 124k triangles, more than
//! the trace at 1024x1024), and a scene rendered again (a CI run, a
//! notebook, a loop moving a light) finds its tree instead.
//!
//! The key holds every f32 corner's digest and the builder's settings, so
//! another mesh, a moved camera (the corners are camera-relative) or
//! another builder misses. An entry is checked before use: its words'
//! digest, and a walk of the tree that every index stays in range and no
//! node is reached twice, so a damaged file is a miss, never a panic or a
//! wrong tree. The CPU twin never reads it: the reference builds its own.

use std::path::Path;

use obvhs::bvh2::node::Bvh2Node;
use obvhs::bvh2::Bvh2;

use super::bvh::{build_from, f32_triangles};
use super::primitives::RtTriangle;
use crate::cache;

/// Triangles below which the tree is built (in under a millisecond), not
/// read from a file.
pub const CACHED_MIN_TRIANGLES: usize = 4096;

/// What the entry's words mean and how the tree was built: a change to
/// either must change this.
const FORMAT: &str = "bvh2 1, obvhs 0.4 medium_build";

const CACHE_KIND: &str = "bvh";

/// Trees the folder keeps (the newest): a few scenes' worth, about 100 MB
/// for meshes of the ogre's size (124k triangles, 3.5 MB an entry).
const KEPT_TREES: usize = 32;

/// Words of a node (`Bvh2Node`: a box of two 16-byte vectors, the count,
/// the first index and two spare words).
const NODE_WORDS: usize = std::mem::size_of::<Bvh2Node>() / 4;

/// The tree over `triangles`: from the cache folder where it holds one for
/// these very corners, else built (and kept there).
pub(super) fn cached_or_built(triangles: &[RtTriangle]) -> Bvh2 {
    cached_or_built_in(cache::folder().as_deref(), triangles)
}

fn cached_or_built_in(folder: Option<&Path>, triangles: &[RtTriangle]) -> Bvh2 {
    let tris = f32_triangles(triangles);
    let Some(folder) = folder.filter(|_| triangles.len() >= CACHED_MIN_TRIANGLES) else {
        return build_from(&tris);
    };
    let corners: Vec<u32> = tris
        .iter()
        .flat_map(|t| [t.v0, t.v1, t.v2])
        .flat_map(|v| v.to_array().map(f32::to_bits))
        .collect();
    let key = format!(
        "{FORMAT}, {} triangles, corners {:016x}",
        triangles.len(),
        cache::digest(&corners)
    );
    let entry = cache::read_words(folder, CACHE_KIND, &key);
    if let Some(tree) = entry.and_then(|w| decode(&w, tris.len())) {
        return tree;
    }
    let tree = build_from(&tris);
    cache::write_words(folder, CACHE_KIND, &key, &encode(&tree));
    // The key holds camera-relative corners, so a camera moved from frame
    // to frame writes an entry a frame: the folder keeps the newest few.
    cache::keep_newest(folder, CACHE_KIND, KEPT_TREES);
    tree
}

/// The entry: the node count, the index count, the payload's digest (two
/// words), then the nodes and the primitive indices.
fn encode(tree: &Bvh2) -> Vec<u32> {
    let mut payload: Vec<u32> = bytemuck::cast_slice(&tree.nodes).to_vec();
    payload.extend_from_slice(&tree.primitive_indices);
    let check = cache::digest(&payload);
    let mut words = vec![
        tree.nodes.len() as u32,
        tree.primitive_indices.len() as u32,
        check as u32,
        (check >> 32) as u32,
    ];
    words.extend(payload);
    words
}

/// The tree an entry holds, if it is whole and a tree over `triangles`
/// primitives.
fn decode(words: &[u32], triangles: usize) -> Option<Bvh2> {
    let (head, payload) = words.split_at_checked(4)?;
    let (nodes, indices) = (head[0] as usize, head[1] as usize);
    let check = u64::from(head[2]) | u64::from(head[3]) << 32;
    if indices != triangles
        || payload.len() != nodes.checked_mul(NODE_WORDS)?.checked_add(indices)?
        || cache::digest(&payload) != check
    {
        return None;
    }
    let (node_words, primitive_indices) = payload.split_at(nodes * NODE_WORDS);
    let tree = Bvh2 {
        nodes: bytemuck::pod_collect_to_vec(node_words),
        primitive_indices: primitive_indices.to_vec(),
        ..Bvh2::default()
    };
    is_tree(&tree, triangles).then_some(tree)
}

/// Whether `tree` is a tree the walks can trust: from node 0 every node
/// reached once, each child pair and leaf run in range, every primitive
/// index below `triangles`.
fn is_tree(tree: &Bvh2, triangles: usize) -> bool {
    let nodes = &tree.nodes;
    if nodes.is_empty()
        || tree
            .primitive_indices
            .iter()
            .any(|&i| i as usize >= triangles)
    {
        return false;
    }
    let mut reached = vec![false; nodes.len()];
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        if std::mem::replace(&mut reached[i], true) {
            return false;
        }
        let node = &nodes[i];
        let first = node.first_index as usize;
        if node.prim_count == 0 {
            if first + 1 >= nodes.len() {
                return false;
            }
            stack.extend([first, first + 1]);
        } else if first + node.prim_count as usize > tree.primitive_indices.len() {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rt_scene::RtScene;
    use crate::scene::{default_scene, tessellate, Object, Shape};
    use glam::DVec3;

    fn sphere_triangles(segments: u32) -> Vec<RtTriangle> {
        let mut scene = default_scene();
        scene.objects = vec![Object {
            shape: Shape::Mesh(tessellate(&Shape::Sphere {
                center: DVec3::new(0.0, 3.0, 0.0),
                radius: 1.0,
                segments,
            })),
            material: 0,
        }];
        RtScene::new(&scene).triangles
    }

    fn same_tree(a: &Bvh2, b: &Bvh2) -> bool {
        bytemuck::cast_slice::<_, u32>(&a.nodes) == bytemuck::cast_slice::<_, u32>(&b.nodes)
            && a.primitive_indices == b.primitive_indices
    }

    /// An entry reads back as the tree written, and only for as many
    /// triangles as it was built over.
    #[test]
    fn an_entry_reads_back_as_the_tree_it_holds() {
        let triangles = sphere_triangles(24);
        let tree = build_from(&f32_triangles(&triangles));
        let words = encode(&tree);
        let back = decode(&words, triangles.len()).expect("a whole entry");
        assert!(same_tree(&back, &tree));
        assert!(decode(&words, triangles.len() + 1).is_none());
    }

    /// A word changed anywhere, a cut entry or a tree whose indices leave
    /// their range reads as a miss, never a panic.
    #[test]
    fn a_damaged_entry_is_a_miss() {
        let triangles = sphere_triangles(24);
        let tree = build_from(&f32_triangles(&triangles));
        let words = encode(&tree);
        for at in [0, 1, 2, 5, 4 + NODE_WORDS * 3 + 1, words.len() - 1] {
            let mut bad = words.clone();
            bad[at] ^= 0x10;
            assert!(decode(&bad, triangles.len()).is_none(), "word {at} changed");
        }
        assert!(decode(&words[..words.len() - 1], triangles.len()).is_none());
        assert!(decode(&words[..3], triangles.len()).is_none());
        // Well-formed words whose tree loops back to its root (the digest
        // recomputed, as a writer with another bug would).
        let mut looped = tree.clone();
        let inner = looped
            .nodes
            .iter()
            .position(|n| n.prim_count == 0 && n.first_index > 0);
        looped.nodes[inner.unwrap()].first_index = 0;
        assert!(decode(&encode(&looped), triangles.len()).is_none());
        let mut out_of_range = tree;
        out_of_range.primitive_indices[0] = triangles.len() as u32;
        assert!(decode(&encode(&out_of_range), triangles.len()).is_none());
    }

    /// Through the cache folder: the first render of a big mesh writes the
    /// entry, the next reads it, and the tree is the one the build gives.
    #[test]
    fn a_big_mesh_finds_its_tree_in_the_cache_folder() {
        let folder = tempfile::tempdir().unwrap();
        let cached = |t: &[RtTriangle]| cached_or_built_in(Some(folder.path()), t);
        let triangles = sphere_triangles(72);
        assert!(triangles.len() >= CACHED_MIN_TRIANGLES);
        let built = build_from(&f32_triangles(&triangles));
        let first = cached(&triangles);
        let entries = || std::fs::read_dir(folder.path().join(CACHE_KIND)).map_or(0, |d| d.count());
        assert_eq!(entries(), 1);
        let second = cached(&triangles);
        assert!(same_tree(&first, &built) && same_tree(&second, &built));
        // Another mesh misses and writes its own entry.
        cached(&sphere_triangles(80));
        assert_eq!(entries(), 2);
    }
}
