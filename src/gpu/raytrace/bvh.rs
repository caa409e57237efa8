//! The GPU ray tracer's one BVH: the mesh triangles' tree (the one the CPU
//! twin walks too) and, beside it, a tree over each kind of analytic object
//! whose list is too long for the shader to test one by one, joined under
//! a few nodes on top. Inner nodes hold both children's boxes (widened as
//! both tracers widen them, `rt_scene::widened_box`); a leaf is a run of one
//! kind's records, named by its index in the leaf index space of
//! `LeafBases`. `docs/raytracing.md` says why.

use glam::{DVec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;

use crate::gpu::raytrace::layout::*;
use crate::gpu::raytrace::wide_bvh::{widen, WideBvh};
use crate::gpu::vk::error::GpuError;
use crate::rt_scene::{widened_box, RtScene};

/// Which kinds of analytic object the BVH holds (the others are tested one
/// by one, in the shader's loops).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BvhKinds {
    pub spheres: bool,
    pub planes: bool,
    pub boxes: bool,
}

impl BvhKinds {
    /// The kinds whose lists are too long to unroll the loop over.
    pub fn of(rt: &RtScene) -> Self {
        BvhKinds {
            spheres: rt.spheres.len() > UNROLLED_SPHERES,
            planes: rt.planes.len() > UNROLLED_PLANES,
            boxes: rt.boxes.len() > UNROLLED_BOXES,
        }
    }

    /// The primitives a BVH of these kinds holds over `rt`: its triangles
    /// and the objects of the kinds it takes.
    pub fn primitives(self, rt: &RtScene) -> usize {
        let count = |on: bool, n: usize| if on { n } else { 0 };
        rt.triangles.len()
            + count(self.spheres, rt.spheres.len())
            + count(self.planes, rt.planes.len())
            + count(self.boxes, rt.boxes.len())
    }
}

/// The leaf index space: triangles from 0, then the BVH's spheres, planes
/// and boxes from these indices on (a leaf's kind is the range its first
/// index falls in; the shader's `frame.leaf_bases`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LeafBases {
    pub spheres: u32,
    pub planes: u32,
    pub boxes: u32,
    /// One past the last index.
    pub end: u32,
}

/// The BVH as the shader walks it.
#[derive(Debug, Clone, Default)]
pub struct GpuBvh {
    pub nodes: Vec<GpuBvhNode>,
    /// The link the walk starts from: an inner node, or a leaf when the
    /// whole tree is one. None for an empty tree.
    pub root: Option<u32>,
    /// The whole tree's box (widened, as its nodes' are), min and max;
    /// None for an empty tree.
    pub bounds: Option<Bounds>,
    pub bases: LeafBases,
    /// Each BVH kind's records in leaf order: record i is object
    /// `order[i]` of its list (empty for a kind the BVH does not hold).
    pub sphere_order: Vec<u32>,
    pub plane_order: Vec<u32>,
    pub box_order: Vec<u32>,
    /// The tree's 4-wide form, which the shader walks where it has one
    /// (`wide_bvh::widen`).
    pub wide: Option<WideBvh>,
}

impl GpuBvh {
    /// A sphere around the whole tree, as centre and radius, the radius
    /// rounded up so that the f32 sphere holds every corner of the tree's
    /// box; radius -1 for an empty tree. The shader skips the walk for a
    /// packet none of whose lines meets it.
    pub fn bounding_sphere(&self) -> [f32; 4] {
        let Some((lo, hi)) = self.bounds else {
            return [0.0, 0.0, 0.0, -1.0];
        };
        let (lo, hi) = (
            DVec3::from(lo.map(f64::from)),
            DVec3::from(hi.map(f64::from)),
        );
        let center = ((lo + hi) * 0.5).as_vec3();
        let reach = (0..8)
            .map(|k| {
                let corner = DVec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                );
                corner.distance(center.as_dvec3())
            })
            .fold(0.0, f64::max);
        // Up by more than the f32 rounding of the radius itself.
        let radius = (reach * (1.0 + 1e-6)) as f32;
        [center.x, center.y, center.z, radius]
    }

    /// The link the shader's walk starts from (None for an empty tree):
    /// the wide form's root where the tree has one.
    pub fn walk_root(&self) -> Option<u32> {
        self.wide.as_ref().map(|w| w.root).or(self.root)
    }

    /// The node records the shader reads, in the form it walks.
    pub fn walk_nodes(&self) -> &[u8] {
        match &self.wide {
            Some(wide) => bytemuck::cast_slice(&wide.nodes),
            None => bytemuck::cast_slice(&self.nodes),
        }
    }

    /// Nodes on the longest path from the root to a leaf, the leaf
    /// counted (0 for an empty tree). The walk stacks at most one link per
    /// inner node on its path, so it needs fewer entries than this.
    pub fn depth(&self) -> usize {
        let Some(root) = self.root else { return 0 };
        let mut deepest = 0;
        let mut stack = vec![(root, 1usize)];
        while let Some((link, depth)) = stack.pop() {
            deepest = deepest.max(depth);
            if link & LEAF_BIT == 0 {
                let node = &self.nodes[link as usize];
                for child in &node.children {
                    stack.push((child.link, depth + 1));
                }
            }
        }
        deepest
    }
}

/// One tree in the node layout, its links not yet placed among the others'.
struct Subtree {
    nodes: Vec<GpuBvhNode>,
    root: u32,
    lo: [f32; 3],
    hi: [f32; 3],
}

/// Builds the BVH of `rt` for the kinds `kinds` says, or says why the
/// shader cannot walk it.
pub fn gpu_bvh(rt: &RtScene, kinds: BvhKinds) -> Result<GpuBvh, GpuError> {
    let objects = |on: bool, bounds: Vec<(DVec3, DVec3)>| on.then(|| object_tree(&bounds));
    let sphere_tree = objects(
        kinds.spheres,
        rt.spheres.iter().map(|s| s.bounds()).collect(),
    );
    let plane_tree = objects(kinds.planes, rt.planes.iter().map(|p| p.bounds()).collect());
    let box_tree = objects(kinds.boxes, rt.boxes.iter().map(|b| b.bounds()).collect());
    let count = |on: bool, n: usize| if on { n } else { 0 };
    let total = kinds.primitives(rt);
    if total > MAX_BVH_PRIMITIVES {
        return Err(GpuError::SceneTooLarge(format!(
            "{total} triangles and listed objects, more than the GPU ray tracer's {MAX_BVH_PRIMITIVES}"
        )));
    }
    let triangles = rt.triangles.len() as u32;
    let bases = LeafBases {
        spheres: triangles,
        planes: triangles + count(kinds.spheres, rt.spheres.len()) as u32,
        boxes: triangles
            + count(kinds.spheres, rt.spheres.len()) as u32
            + count(kinds.planes, rt.planes.len()) as u32,
        end: total as u32,
    };
    let mut parts = Vec::new();
    if !rt.triangles.is_empty() {
        parts.push(subtree(&rt.bvh, 0)?);
    }
    let order = |tree: &Option<Bvh2>| {
        tree.as_ref()
            .map_or(Vec::new(), |t| t.primitive_indices.clone())
    };
    for (tree, base) in [
        (&sphere_tree, bases.spheres),
        (&plane_tree, bases.planes),
        (&box_tree, bases.boxes),
    ] {
        if let Some(tree) = tree {
            parts.push(subtree(tree, base)?);
        }
    }
    let (nodes, root, bounds) = join(parts);
    let mut bvh = GpuBvh {
        wide: None,
        nodes,
        root,
        bounds,
        bases,
        sphere_order: order(&sphere_tree),
        plane_order: order(&plane_tree),
        box_order: order(&box_tree),
    };
    // The shader's stack would drop nodes (rays would miss).
    let depth = bvh.depth();
    if depth >= BVH_STACK_SIZE {
        return Err(GpuError::BvhTooDeep {
            depth,
            limit: BVH_STACK_SIZE - 1,
        });
    }
    // After the depth's check, which bounds widen's recursion.
    bvh.wide = widen(&bvh.nodes, bvh.root);
    Ok(bvh)
}

/// A tree over objects' boxes (min, max) rounded to f32, as the triangles'
/// is built over their f32 corners: `subtree` widens every node's box,
/// which covers the rounding (as it does the triangles').
fn object_tree(bounds: &[(DVec3, DVec3)]) -> Bvh2 {
    let aabbs: Vec<Aabb> = bounds
        .iter()
        .map(|&(lo, hi)| Aabb {
            min: Vec3A::from(lo.as_vec3()),
            max: Vec3A::from(hi.as_vec3()),
        })
        .collect();
    let mut build_time = std::time::Duration::default();
    obvhs::bvh2::builder::build_bvh2(
        &aabbs,
        obvhs::BvhBuildParams::medium_build(),
        &mut build_time,
    )
}

/// A binary tree (children at `first_index` and the one after it; node 0
/// the root) re-linked so that each inner node holds its children's boxes,
/// its leaves' runs moved to start at `base` in the leaf index space.
fn subtree(tree: &Bvh2, base: u32) -> Result<Subtree, GpuError> {
    let nodes = &tree.nodes;
    // Inner nodes keep their relative order; `slot[i]` is node i's new index.
    let mut slot = vec![u32::MAX; nodes.len()];
    let mut inner = 0u32;
    for (i, node) in nodes.iter().enumerate() {
        if node.prim_count == 0 {
            slot[i] = inner;
            inner += 1;
        }
    }
    let link = |i: usize| -> Result<u32, GpuError> {
        let node = &nodes[i];
        if node.prim_count == 0 {
            return Ok(slot[i]);
        }
        if node.prim_count > MAX_LEAF_PRIMITIVES {
            return Err(GpuError::SceneTooLarge(format!(
                "a BVH leaf of {} primitives, more than the GPU ray tracer's {MAX_LEAF_PRIMITIVES}",
                node.prim_count
            )));
        }
        Ok(leaf_link(base + node.first_index, node.prim_count))
    };
    let bounds = |i: usize| {
        let aabb = nodes[i].aabb();
        let (lo, hi) = widened_box(aabb.min.as_dvec3(), aabb.max.as_dvec3());
        (v3(lo), v3(hi))
    };
    let (lo, hi) = bounds(0);
    let mut linked = Vec::with_capacity(inner as usize);
    let child = |i: usize| -> Result<GpuBvhChild, GpuError> {
        let (lo, hi) = bounds(i);
        Ok(GpuBvhChild::new(lo, link(i)?, hi))
    };
    for node in nodes.iter().filter(|n| n.prim_count == 0) {
        let left = node.first_index as usize;
        linked.push(GpuBvhNode {
            children: [child(left)?, child(left + 1)?],
        });
    }
    Ok(Subtree {
        nodes: linked,
        root: link(0)?,
        lo,
        hi,
    })
}

/// The subtrees' nodes in one array, under new nodes that pair their roots
/// up; returns the nodes, the root's link and the whole tree's box.
fn join(parts: Vec<Subtree>) -> (Vec<GpuBvhNode>, Option<u32>, Option<Bounds>) {
    let mut nodes = Vec::new();
    let mut roots = Vec::new();
    for part in parts {
        let offset = nodes.len() as u32;
        let place = |link: u32| {
            if link & LEAF_BIT == 0 {
                link + offset
            } else {
                link
            }
        };
        nodes.extend(part.nodes.iter().map(|n| GpuBvhNode {
            children: n.children.map(|c| GpuBvhChild {
                link: place(c.link),
                ..c
            }),
        }));
        roots.push((place(part.root), part.lo, part.hi));
    }
    while roots.len() > 1 {
        let (right, right_lo, right_hi) = roots.pop().unwrap_or_default();
        let (left, left_lo, left_hi) = roots.pop().unwrap_or_default();
        nodes.push(GpuBvhNode {
            children: [
                GpuBvhChild::new(left_lo, left, left_hi),
                GpuBvhChild::new(right_lo, right, right_hi),
            ],
        });
        let lo = std::array::from_fn(|k| left_lo[k].min(right_lo[k]));
        let hi = std::array::from_fn(|k| left_hi[k].max(right_hi[k]));
        roots.push((nodes.len() as u32 - 1, lo, hi));
    }
    let root = roots.first();
    (nodes, root.map(|r| r.0), root.map(|&(_, lo, hi)| (lo, hi)))
}

/// A box's min and max corners.
pub type Bounds = ([f32; 3], [f32; 3]);

fn v3(v: DVec3) -> [f32; 3] {
    v.as_vec3().to_array()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{default_scene, tessellate, Object, Shape};
    use glam::DMat3;

    /// The default scene with a tessellated sphere and lists of every kind
    /// long enough to go into the BVH.
    fn crowded() -> RtScene {
        let mut scene = default_scene();
        let sphere = |center: DVec3, radius: f64| Shape::Sphere {
            center,
            radius,
            segments: 24,
        };
        scene.objects.push(Object {
            shape: Shape::Mesh(tessellate(&sphere(DVec3::new(0.0, 3.0, 0.0), 1.0))),
            material: 0,
        });
        for i in 0..20 {
            let x = f64::from(i);
            scene.objects.push(Object {
                shape: sphere(DVec3::new(x - 10.0, 0.5, -4.0), 0.3 + 0.01 * x),
                material: 0,
            });
            if i < 14 {
                scene.objects.push(Object {
                    shape: Shape::Plane {
                        center: DVec3::new(x - 7.0, -1.0, 3.0),
                        normal: DVec3::new(0.2, 1.0, 0.1 * x).normalize(),
                        size: 0.8,
                        segments: 1,
                    },
                    material: 0,
                });
            }
            if i < 9 {
                scene.objects.push(Object {
                    shape: Shape::Box {
                        center: DVec3::new(x - 4.0, 1.0, 5.0),
                        half_extents: DVec3::new(0.3, 0.5, 0.2),
                        rotation: DMat3::from_rotation_y(0.4 * x) * DMat3::from_rotation_x(0.3),
                    },
                    material: 0,
                });
            }
        }
        RtScene::new(&scene)
    }

    /// Every triangle and every object of a kind the BVH holds sits in
    /// exactly one leaf, in its kind's range of the leaf index space, and
    /// inside every box on its way from the root: a ray that reaches it
    /// through no box would miss it. The walk's stack stays within
    /// `depth`, which `gpu_bvh` holds under the shader's stack size.
    #[test]
    fn every_primitive_is_in_one_leaf_of_its_kind_inside_the_boxes_above_it() {
        let rt = crowded();
        let kinds = BvhKinds::of(&rt);
        assert_eq!(
            kinds,
            BvhKinds {
                spheres: true,
                planes: true,
                boxes: true
            }
        );
        let bvh = gpu_bvh(&rt, kinds).unwrap();
        let b = bvh.bases;
        let triangles = rt.triangles.len() as u32;
        assert_eq!(b.spheres, triangles);
        assert_eq!(b.planes, b.spheres + rt.spheres.len() as u32);
        assert_eq!(b.boxes, b.planes + rt.planes.len() as u32);
        assert_eq!(b.end, b.boxes + rt.boxes.len() as u32);
        // The f64 bounds of the primitive at leaf index j.
        let bounds = |j: u32| -> (DVec3, DVec3) {
            if j < b.spheres {
                let t = &rt.triangles[rt.bvh.primitive_indices[j as usize] as usize];
                let [p, q, r] = t.positions;
                (p.min(q).min(r), p.max(q).max(r))
            } else if j < b.planes {
                rt.spheres[bvh.sphere_order[(j - b.spheres) as usize] as usize].bounds()
            } else if j < b.boxes {
                rt.planes[bvh.plane_order[(j - b.planes) as usize] as usize].bounds()
            } else {
                rt.boxes[bvh.box_order[(j - b.boxes) as usize] as usize].bounds()
            }
        };
        let inside = |(lo, hi): (DVec3, DVec3), (box_lo, box_hi): ([f32; 3], [f32; 3])| {
            let (box_lo, box_hi) = (
                glam::Vec3::from(box_lo).as_dvec3(),
                glam::Vec3::from(box_hi).as_dvec3(),
            );
            box_lo.cmple(lo).all() && hi.cmple(box_hi).all()
        };
        let mut seen = vec![0u32; b.end as usize];
        let mut most = 0;
        // (link, the boxes on its way from the root)
        let mut stack = vec![(bvh.root.unwrap(), Vec::new())];
        while let Some((link, boxes)) = stack.pop() {
            if link & LEAF_BIT != 0 {
                let first = link & 0x03ff_ffff;
                let count = ((link >> 26) & 31) + 1;
                let kind = |j: u32| {
                    [b.spheres, b.planes, b.boxes]
                        .iter()
                        .filter(|&&s| j >= s)
                        .count()
                };
                for j in first..first + count {
                    assert_eq!(kind(j), kind(first), "a leaf mixes kinds at {j}");
                    seen[j as usize] += 1;
                    for &bx in &boxes {
                        assert!(inside(bounds(j), bx), "primitive {j} pokes out of {bx:?}");
                    }
                }
                continue;
            }
            let node = &bvh.nodes[link as usize];
            for child in node.children.iter().rev() {
                let mut path = boxes.clone();
                path.push((child.lo, child.hi));
                stack.push((child.link, path));
            }
            most = most.max(stack.len());
        }
        assert!(seen.iter().all(|&n| n == 1), "{seen:?}");
        let depth = bvh.depth();
        assert!(
            most < depth,
            "the walk needed {most} entries, depth {depth}"
        );
        assert!(depth < BVH_STACK_SIZE);
    }

    /// Short lists stay out of the BVH, and a scene of them alone has none.
    #[test]
    fn short_lists_are_tested_one_by_one() {
        let rt = RtScene::new(&default_scene());
        let kinds = BvhKinds::of(&rt);
        assert_eq!(kinds, BvhKinds::default());
        let bvh = gpu_bvh(&rt, kinds).unwrap();
        assert!(bvh.root.is_none() && bvh.nodes.is_empty() && bvh.depth() == 0);
        assert_eq!(bvh.bounding_sphere()[3], -1.0, "no tree, no sphere");
    }

    /// The sphere the shader tests a packet's lines against before the walk
    /// holds, in f32, every primitive's box (a primitive outside it would be
    /// missed by every ray), and is not much larger than the tree's box.
    #[test]
    fn the_bounding_sphere_holds_every_primitive() {
        let rt = crowded();
        let bvh = gpu_bvh(&rt, BvhKinds::of(&rt)).unwrap();
        let [x, y, z, radius] = bvh.bounding_sphere();
        let center = glam::Vec3::new(x, y, z);
        let mut boxes: Vec<(DVec3, DVec3)> = rt
            .triangles
            .iter()
            .map(|t| {
                let p = t.positions.map(|p| p.as_vec3().as_dvec3());
                (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]))
            })
            .collect();
        boxes.extend(rt.spheres.iter().map(|s| s.bounds()));
        boxes.extend(rt.planes.iter().map(|p| p.bounds()));
        boxes.extend(rt.boxes.iter().map(|b| b.bounds()));
        let mut farthest = 0.0f32;
        for (lo, hi) in boxes {
            for k in 0..8 {
                let corner = glam::Vec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x } as f32,
                    if k & 2 == 0 { lo.y } else { hi.y } as f32,
                    if k & 4 == 0 { lo.z } else { hi.z } as f32,
                );
                farthest = farthest.max(corner.distance(center));
            }
        }
        assert!(
            farthest <= radius,
            "a corner at {farthest}, radius {radius}"
        );
        let (lo, hi) = bvh.bounds.unwrap();
        let half_diagonal = glam::Vec3::from(hi).distance(glam::Vec3::from(lo)) / 2.0;
        assert!(
            radius <= half_diagonal * 1.001,
            "radius {radius}, half diagonal {half_diagonal}"
        );
    }
}
