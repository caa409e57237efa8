//! The walk of the scene's BVH: its `f32` boxes widened into `f64` once,
//! then visited depth-first with a small inline stack.

use std::ops::ControlFlow;

use glam::DVec3;

use super::hit::Ray;
use crate::rt_scene::{widened_box, RtScene};

/// A BVH node with its f32 bounds widened in f64, so that no f64 triangle
/// (whose f32 rounding the bounds were built from) pokes out of it.
#[derive(Debug, Clone, Copy)]
struct Node {
    min: DVec3,
    max: DVec3,
    prim_count: u32,
    first_index: u32,
}

/// Entry distance of a ray into an axis-aligned box, if it meets the box at
/// some `t` in `[0, t_max]`.
#[inline]
fn box_entry(ray: &Ray, min: DVec3, max: DVec3, t_max: f64) -> Option<f64> {
    let (mut lo, mut hi) = (0.0f64, t_max);
    for axis in 0..3 {
        let (o, d) = (ray.origin[axis], ray.dir[axis]);
        if d == 0.0 {
            if o < min[axis] || o > max[axis] {
                return None;
            }
            continue;
        }
        let ta = (min[axis] - o) / d;
        let tb = (max[axis] - o) / d;
        let (near, far) = if ta < tb { (ta, tb) } else { (tb, ta) };
        lo = lo.max(near);
        hi = hi.min(far);
        if lo > hi {
            return None;
        }
    }
    Some(lo)
}

/// A traversal stack: 64 entries inline, more on the heap only for a tree
/// deeper than that.
struct NodeStack {
    inline: [u32; 64],
    len: usize,
    spill: Vec<u32>,
}

impl NodeStack {
    #[inline]
    fn new(root: u32) -> Self {
        let mut s = NodeStack {
            inline: [0; 64],
            len: 0,
            spill: Vec::new(),
        };
        s.push(root);
        s
    }

    #[inline]
    fn push(&mut self, node: u32) {
        if self.len < self.inline.len() {
            self.inline[self.len] = node;
            self.len += 1;
        } else {
            self.spill.push(node);
        }
    }

    #[inline]
    fn pop(&mut self) -> Option<u32> {
        if let Some(node) = self.spill.pop() {
            return Some(node);
        }
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        Some(self.inline[self.len])
    }
}

/// The BVH of an `RtScene` with its boxes widened in `f64`.
pub(super) struct WidenedBvh<'a> {
    nodes: Vec<Node>,
    /// The triangle indices the leaves' runs point into.
    primitive_indices: &'a [u32],
}

impl<'a> WidenedBvh<'a> {
    pub(super) fn new(scene: &'a RtScene) -> Self {
        let nodes = if scene.triangles.is_empty() {
            Vec::new()
        } else {
            scene
                .bvh
                .nodes
                .iter()
                .map(|n| {
                    let aabb = n.aabb();
                    let (min, max) = widened_box(aabb.min.as_dvec3(), aabb.max.as_dvec3());
                    Node {
                        min,
                        max,
                        prim_count: n.prim_count,
                        first_index: n.first_index,
                    }
                })
                .collect()
        };
        WidenedBvh {
            nodes,
            primitive_indices: &scene.bvh.primitive_indices,
        }
    }

    /// Walks the BVH depth-first, handing `leaf` the triangle indices of
    /// every leaf whose box the ray enters before `t_max`. `leaf` may lower
    /// `t_max` (a nearer hit) or break off the walk (any hit will do).
    pub(super) fn walk(
        &self,
        ray: &Ray,
        mut t_max: f64,
        mut leaf: impl FnMut(&[u32], &mut f64) -> ControlFlow<()>,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = NodeStack::new(0);
        while let Some(index) = stack.pop() {
            let node = &self.nodes[index as usize];
            if box_entry(ray, node.min, node.max, t_max).is_none() {
                continue;
            }
            if node.prim_count == 0 {
                stack.push(node.first_index);
                stack.push(node.first_index + 1);
                continue;
            }
            let first = node.first_index as usize;
            let indices = &self.primitive_indices[first..first + node.prim_count as usize];
            if leaf(indices, &mut t_max).is_break() {
                return;
            }
        }
    }
}
