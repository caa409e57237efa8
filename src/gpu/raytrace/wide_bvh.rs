//! The BVH's 4-wide form, which the shader walks on a big tree: each inner
//! node holds up to four children, a binary node's children replaced by
//! theirs (the largest box first) until there are four. The boxes are the
//! binary tree's, so a ray enters the same leaves either way and finds the
//! same nearest hit. A step of the wide walk reads and tests twice the
//! boxes of a binary one and the walk takes about half the steps: on a big
//! tree that saves the per-step work (the packet's vote, the choice of the
//! child, the loop), on a small one it costs more than it saves
//! (docs/performance.md, "What each change bought").

use bytemuck::Zeroable;

use crate::gpu::raytrace::layout::*;

/// Inner nodes of the binary tree from which the shader walks the wide
/// form instead (measured: docs/performance.md).
pub const WIDE_MIN_INNER_NODES: usize = 32;

/// The 4-wide tree as the shader walks it.
#[derive(Debug, Clone, PartialEq)]
pub struct WideBvh {
    pub nodes: Vec<GpuWideNode>,
    /// The inner node the walk starts from.
    pub root: u32,
}

impl WideBvh {
    /// Stack entries the walk may need: at a node of n children it stacks
    /// n - 1 and goes on into any of them (the nearer first, which only
    /// the rays know).
    pub fn stack_need(&self) -> usize {
        fn need(nodes: &[GpuWideNode], index: u32) -> usize {
            let children = &nodes[index as usize].children;
            let used = children.iter().filter(|c| c.link != NO_CHILD).count();
            let deepest = children
                .iter()
                .filter(|c| c.link != NO_CHILD && c.link & LEAF_BIT == 0)
                .map(|c| need(nodes, c.link))
                .max()
                .unwrap_or(0);
            used - 1 + deepest
        }
        need(&self.nodes, self.root)
    }
}

/// The 4-wide form of the binary tree `nodes` under `root`, or None where
/// the binary walk is the faster (fewer than `WIDE_MIN_INNER_NODES` inner
/// nodes) or the wide walk's stack would overflow.
pub fn widen(nodes: &[GpuBvhNode], root: Option<u32>) -> Option<WideBvh> {
    let root = root.filter(|r| r & LEAF_BIT == 0)?;
    if nodes.len() < WIDE_MIN_INNER_NODES {
        return None;
    }
    let mut wide = Vec::with_capacity(nodes.len() / 2 + 1);
    let root = widen_node(nodes, root, &mut wide);
    let tree = WideBvh { nodes: wide, root };
    (tree.stack_need() <= BVH_STACK_SIZE).then_some(tree)
}

/// Half the surface area of a child's box: the chance a ray through its
/// parent enters it, up to a factor.
fn area(child: &GpuBvhChild) -> f32 {
    let [x, y, z] = std::array::from_fn(|k| child.hi[k] - child.lo[k]);
    x * y + y * z + z * x
}

/// Places binary node `index` and its subtree in `wide`; returns its index
/// there. Parents come before their children.
fn widen_node(nodes: &[GpuBvhNode], index: u32, wide: &mut Vec<GpuWideNode>) -> u32 {
    let mut children = nodes[index as usize].children.to_vec();
    while children.len() < 4 {
        let largest_inner = children
            .iter()
            .enumerate()
            .filter(|(_, c)| c.link & LEAF_BIT == 0)
            .max_by(|a, b| area(a.1).total_cmp(&area(b.1)))
            .map(|(i, _)| i);
        let Some(i) = largest_inner else { break };
        let pair = nodes[children[i].link as usize].children;
        children.splice(i..=i, pair);
    }
    let slot = wide.len();
    wide.push(GpuWideNode::zeroed());
    let mut node = GpuWideNode {
        children: [GpuBvhChild {
            link: NO_CHILD,
            ..GpuBvhChild::zeroed()
        }; 4],
    };
    for (k, child) in children.iter().enumerate() {
        let link = if child.link & LEAF_BIT == 0 {
            widen_node(nodes, child.link, wide)
        } else {
            child.link
        };
        node.children[k] = GpuBvhChild { link, ..*child };
    }
    wide[slot] = node;
    slot as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::raytrace::bvh::{gpu_bvh, BvhKinds};
    use crate::rt_scene::RtScene;
    use crate::scene::{default_scene, tessellate, Object, Shape};
    use glam::DVec3;

    fn mesh_sphere(segments: u32) -> RtScene {
        let mut scene = default_scene();
        scene.objects.push(Object {
            shape: Shape::Mesh(tessellate(&Shape::Sphere {
                center: DVec3::new(0.0, 3.0, 0.0),
                radius: 1.0,
                segments,
            })),
            material: 0,
        });
        RtScene::new(&scene)
    }

    /// Every leaf of the binary tree, with the box its parent gave it.
    fn binary_leaves(nodes: &[GpuBvhNode], link: u32, out: &mut Vec<([f32; 3], u32, [f32; 3])>) {
        let node = &nodes[link as usize];
        for child in node.children {
            if child.link & LEAF_BIT != 0 {
                out.push((child.lo, child.link, child.hi));
            } else {
                binary_leaves(nodes, child.link, out);
            }
        }
    }

    /// The wide tree has the binary tree's leaves, each once and with the
    /// same box; every child's box holds the boxes below it (a ray that
    /// would reach a leaf still does); a node has 2 to 4 children, the used
    /// slots first, and 4 wherever its subtree has 4 leaves or more; its
    /// nodes are about half the binary tree's.
    #[test]
    fn the_wide_tree_has_the_binary_trees_leaves_under_the_same_boxes() {
        let rt = mesh_sphere(48);
        let bvh = gpu_bvh(&rt, BvhKinds::of(&rt)).unwrap();
        let wide = bvh.wide.clone().expect("a big tree is walked wide");
        let mut expected = Vec::new();
        binary_leaves(&bvh.nodes, bvh.root.unwrap(), &mut expected);
        // Returns the leaves under `index`, checking the node on the way.
        fn walk(wide: &WideBvh, index: u32, out: &mut Vec<([f32; 3], u32, [f32; 3])>) -> usize {
            let children = &wide.nodes[index as usize].children;
            let used = children.iter().take_while(|c| c.link != NO_CHILD).count();
            assert!((2..=4).contains(&used), "node {index}: {used} children");
            assert!(children[used..].iter().all(|c| c.link == NO_CHILD));
            let mut leaves = 0;
            for child in &children[..used] {
                if child.link & LEAF_BIT != 0 {
                    out.push((child.lo, child.link, child.hi));
                    leaves += 1;
                    continue;
                }
                let before = out.len();
                leaves += walk(wide, child.link, out);
                for (lo, _, hi) in &out[before..] {
                    assert!((0..3).all(|k| child.lo[k] <= lo[k] && hi[k] <= child.hi[k]));
                }
            }
            assert!(
                used == 4 || leaves == used,
                "node {index}: {used} children over {leaves} leaves"
            );
            leaves
        }
        let mut found = Vec::new();
        walk(&wide, wide.root, &mut found);
        let key = |l: &([f32; 3], u32, [f32; 3])| l.1;
        expected.sort_by_key(key);
        found.sort_by_key(key);
        assert_eq!(found, expected);
        assert!(wide.nodes.len() * 2 <= bvh.nodes.len() + 1);
        assert!(wide.stack_need() <= BVH_STACK_SIZE);
    }

    /// A tree below `WIDE_MIN_INNER_NODES` inner nodes keeps the binary
    /// walk, and so does a tree that is one leaf.
    #[test]
    fn small_trees_keep_the_binary_walk() {
        let rt = mesh_sphere(4);
        let bvh = gpu_bvh(&rt, BvhKinds::of(&rt)).unwrap();
        assert!(!bvh.nodes.is_empty() && bvh.nodes.len() < WIDE_MIN_INNER_NODES);
        assert!(bvh.wide.is_none());
        assert!(widen(&bvh.nodes, Some(leaf_link(0, 1))).is_none());
        assert!(widen(&[], None).is_none());
    }

    /// A chain of binary nodes (each with a leaf and the next node): the
    /// wide nodes take four children each, three of them leaves, so the
    /// walk stacks three entries per node it passes; `stack_need` counts
    /// them, and a tree whose walk would need more than the shader's stack
    /// has no wide form.
    #[test]
    fn the_stack_need_counts_the_entries_stacked_on_the_way_down() {
        let chain = |inner: u32| -> Vec<GpuBvhNode> {
            (0..inner)
                .map(|i| {
                    let next = if i + 1 < inner {
                        i + 1
                    } else {
                        leaf_link(i + 1, 1)
                    };
                    GpuBvhNode {
                        children: [
                            GpuBvhChild::new([0.0; 3], leaf_link(i, 1), [1.0; 3]),
                            GpuBvhChild::new([0.0; 3], next, [2.0; 3]),
                        ],
                    }
                })
                .collect()
        };
        // 33 binary nodes: 11 wide ones of 3 leaves and the next node,
        // the last of 4 leaves; 3 entries stacked at each.
        let wide = widen(&chain(33), Some(0)).unwrap();
        assert_eq!(wide.nodes.len(), 11);
        assert_eq!(wide.stack_need(), 33);
        // 64 binary nodes: 21 wide nodes stacking 3 and a last of 2
        // leaves stacking 1, 64 in all; one binary node more makes it 65.
        assert_eq!(widen(&chain(64), Some(0)).unwrap().stack_need(), 64);
        assert_eq!(BVH_STACK_SIZE, 64);
        assert!(widen(&chain(65), Some(0)).is_none());
    }
}
