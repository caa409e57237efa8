// The ray tracer's BVH walk (walk_bvh): the subgroup's rays as one packet
// through the binary tree, or the 4-wide one when compiled with WIDE_BVH.
#ifndef RT_BVH_GLSL
#define RT_BVH_GLSL

#include "kernel_sizes.glsl"
#include "rt_interface.glsl"
#include "rt_ray.glsl"
#include "rt_packet.glsl"
#include "rt_hit_rule.glsl"
#include "rt_objects.glsl"
#include "rt_primitives.glsl"

// The smaller and the larger of two numbers that are not NaN, as one
// comparison each: lavapipe's min() and max() also sort out a NaN operand,
// three instructions where this takes one.
float smaller(float a, float b) {
    return a < b ? a : b;
}

float larger(float a, float b) {
    return a > b ? a : b;
}

// Entry distance of the ray into a box (the slab test against [0, t_max]),
// or NO_HIT if it misses; a negative t_max misses every box. `inv_d` is
// finite (walk_bvh's `slab_inverse`), so no product here is NaN: for a
// zero direction component the slab test sorts that axis out (lo - o and
// hi - o of the same sign: no t at all; a ray inside the slab, or on one of
// its faces as the CPU twin counts it: all t).
float box_entry(vec3 o, vec3 inv_d, vec3 lo, vec3 hi, float t_max) {
    vec3 t1 = (lo - o) * inv_d;
    vec3 t2 = (hi - o) * inv_d;
    bvec3 t1_first = lessThan(t1, t2);
    vec3 t_in = mix(t2, t1, t1_first);
    vec3 t_out = mix(t1, t2, t1_first);
    float enter = larger(larger(t_in.x, t_in.y), larger(t_in.z, 0.0));
    float leave = smaller(smaller(t_out.x, t_out.y), smaller(t_out.z, t_max));
    return enter <= leave ? enter : NO_HIT;
}

// 1 / d for the slab test, with a zero component's infinity made the
// largest float: (lo - o) * inv_d is then never 0 * infinity (NaN) for a
// ray lying on a slab's face, and a product too large for a float is still
// an infinity of the right sign.
vec3 slab_inverse(vec3 d) {
    const float LARGEST = 3.4028235e38;
    return clamp(vec3(1.0) / d, vec3(-LARGEST), vec3(LARGEST));
}

#ifdef WIDE_BVH
// The wide step's moves (macros: the stack arrays stay the walk's own,
// where a function would copy them in and out). WIDE_STACK stacks a child
// if `cond`; WIDE_TAKE, for a child entered (`bit` set in `enters`), stacks
// the child taken so far and takes this one.
#define WIDE_STACK(cond, child, t)  \
    if (cond) {                     \
        stack_link[top] = child;    \
        stack_t[top] = t;           \
        ++top;                      \
    }
#define WIDE_TAKE(bit, child, t)                      \
    if ((enters & (bit)) != 0u) {                     \
        WIDE_STACK(link != NO_SHAPE, link, t_link)    \
        link = child;                                 \
        t_link = t;                                   \
    }

// Two children in the order of their keys (lane 0's entry distances).
void order_children(inout float ka, inout uint la, inout float ta, inout float kb, inout uint lb, inout float tb) {
    bool swap = kb < ka;
    float k = ka;
    uint l = la;
    float t = ta;
    ka = swap ? kb : ka;
    la = swap ? lb : la;
    ta = swap ? tb : ta;
    kb = swap ? k : kb;
    lb = swap ? l : lb;
    tb = swap ? t : tb;
}

// A 4-wide node's children (gpu::raytrace::wide_bvh) against the packet: each child's
// entry distance for this lane's ray and its link, and one butterfly for
// which of them some lane enters (bit k: child k).
struct WideChildren {
    float t0, t1, t2, t3;
    uint l0, l1, l2, l3;
    uint enters;
};

// The entry distances of a 4-wide node's children for one ray (NO_HIT
// where it misses one within t_max).
vec4 wide_entries(Shared node, vec3 o, vec3 inv_d, float t_max) {
    return vec4(box_entry(o, inv_d, vec3_at(node, CHILD_LO), vec3_at(node, CHILD_HI), t_max),
                box_entry(o, inv_d, vec3_at(node, CHILD_WORDS + CHILD_LO), vec3_at(node, CHILD_WORDS + CHILD_HI),
                          t_max),
                box_entry(o, inv_d, vec3_at(node, 2u * CHILD_WORDS + CHILD_LO),
                          vec3_at(node, 2u * CHILD_WORDS + CHILD_HI), t_max),
                box_entry(o, inv_d, vec3_at(node, 3u * CHILD_WORDS + CHILD_LO),
                          vec3_at(node, 3u * CHILD_WORDS + CHILD_HI), t_max));
}

// Bit k set where child k is entered.
uint entered_bits(vec4 t) {
    return (t.x != NO_HIT ? 1u : 0u) | (t.y != NO_HIT ? 2u : 0u) | (t.z != NO_HIT ? 4u : 0u) |
           (t.w != NO_HIT ? 8u : 0u);
}

WideChildren wide_children(uint link, vec3 o, vec3 inv_d, float t_max) {
    Shared node = read_wide_node(link);
    vec4 t = wide_entries(node, o, inv_d, t_max);
    uint l0 = word(node, CHILD_LINK);
    uint l1 = word(node, CHILD_WORDS + CHILD_LINK);
    uint l2 = word(node, 2u * CHILD_WORDS + CHILD_LINK);
    uint l3 = word(node, 3u * CHILD_WORDS + CHILD_LINK);
    uint enters = or_lanes(entered_bits(t));
    enters &= (l0 != NO_SHAPE ? 1u : 0u) | (l1 != NO_SHAPE ? 2u : 0u) | (l2 != NO_SHAPE ? 4u : 0u) |
              (l3 != NO_SHAPE ? 8u : 0u);
    return WideChildren(t.x, t.y, t.z, t.w, l0, l1, l2, l3, enters);
}
#endif

// A hit on an analytic object in a BVH leaf: like `consider_object`, but
// `best` may be a triangle or an object found in another leaf, so a tie
// takes the general rule. For the shadow query (`any_hit`), any hit nearer
// than best.t ends the lane's search, as for triangles.
void consider_in_leaf(float t, uint shape, vec3 normal, float radius, uint material, uint object, bool any_hit,
                      inout Hit best) {
    if (any_hit) {
        if (t > 0.0 && t < best.t) {
            best = Hit(-1.0, shape, vec2(0.0), vec3(0.0), 0.0, 0u, 0u);
        }
    } else if (t > 0.0 && t <= best.t && (t < best.t || wins_tie(shape, best))) {
        best = Hit(t, shape, vec2(0.0), normal, radius, material, object);
    }
}

void search_leaf_objects(uint first, uint end, vec3 o, vec3 d, bool any_hit, inout Hit best);

// A BVH leaf's primitives against the packet, into walk_bvh's `best`
// (whose comment says what it holds for each query). A leaf is a run of
// one kind's records, the kind given by the range its first index is in
// (uniform: the whole packet is here).
void search_leaf(uint link, vec3 o, vec3 d, RayFrame shear, bool any_hit, inout Hit best) {
    uint first = link & 0x03ffffffu;
    uint end = first + ((link >> 26) & 31u) + 1u;
    if (first < frame.leaf_bases.x) {
        for (uint i = first; i < end; ++i) {
            Shared tri = read_triangle(i);
            vec2 uv;
            float t = triangle_t(shear, tri, uv);
            if (any_hit) {
                if (t > 0.0 && t < best.t) {
                    best = Hit(-1.0, KIND_TRIANGLE | i, uv, vec3(0.0), 0.0, 0u, 0u);
                }
            } else {
                consider_triangle(t, KIND_TRIANGLE | i, uv, best);
            }
        }
    } else {
        search_leaf_objects(first, end, o, d, any_hit, best);
    }
}

// A leaf of analytic objects (search_leaf's other kinds).
void search_leaf_objects(uint first, uint end, vec3 o, vec3 d, bool any_hit, inout Hit best) {
    if (BVH_SPHERES && first < frame.leaf_bases.y) {
        for (uint i = first - frame.leaf_bases.x; i < end - frame.leaf_bases.x; ++i) {
            SphereGeometry g = shared_sphere(i);
            consider_in_leaf(sphere_t(o, d, g), KIND_SPHERE | i, g.center, g.radius, g.material, g.object,
                             any_hit, best);
        }
    } else if (BVH_PLANES && first < frame.leaf_bases.z) {
        for (uint i = first - frame.leaf_bases.y; i < end - frame.leaf_bases.y; ++i) {
            PlaneGeometry g = shared_plane(i);
            consider_in_leaf(plane_t(o, d, g), KIND_PLANE | i, g.normal, 0.0, g.material, g.object, any_hit,
                             best);
        }
    } else if (BVH_BOXES) {
        for (uint i = first - frame.leaf_bases.z; i < end - frame.leaf_bases.z; ++i) {
            BoxGeometry g = shared_box(i);
            vec2 face;
            float t = box_t(o, d, g, face);
            consider_in_leaf(t, KIND_BOX | i, box_normal(g, face), 0.0, g.material, g.object, any_hit, best);
        }
    }
}

// The BVH's primitives (triangles, and the objects of long lists), the
// subgroup's rays as one packet (call in uniform control flow, and only
// where `packet_near_bvh` holds: some lane's ray may reach the tree). Each
// lane's ray takes part up to best.t (negative: not at all). A node is visited when any lane's ray enters its
// box within that lane's limit; of two children both entered, the one lane 0
// enters first goes first and the other waits on the stack with every
// lane's entry distance, to be skipped when popped if no lane can still
// find a nearer hit in it. A lane tests everything its own walk would have
// reached, and more, so its nearest hit (ties included) is what a walk of
// its own would give. Compiled with WIDE_BVH, a step tests a 4-wide node's
// children (gpu::raytrace::wide_bvh) the same way, the entered ones in the order lane 0
// enters them (a shadow query, which visits them all, in slot order).
//
// Nearest hit (`any_hit` false): best is the nearest hit. Shadow query
// (`any_hit`): a lane that finds a hit nearer than best.t stops there, its
// best.shape set and best.t made negative.
void walk_bvh(vec3 o, vec3 d, inout Hit best, bool any_hit) {
    uint link = frame.grid.w;  // the root: node 0, or a leaf
    vec3 inv_d = slab_inverse(d);
    RayFrame shear = ray_frame(o, d);
    // Cannot overflow: the host refuses a tree deeper than the stack
    // (kernel_sizes::BVH_STACK_SIZE), since a dropped node would be a miss,
    // and walks a tree 4-wide only where that walk's stack fits too
    // (wide_bvh::WideBvh::stack_need).
    uint stack_link[BVH_STACK_SIZE];
    float stack_t[BVH_STACK_SIZE];
    int top = 0;
    // The caller's packet_near_bvh has already asked whether any lane has
    // a ray to trace.
    bool done = false;
    while (!done) {
        if ((link & LEAF_BIT) == 0u) {
#ifdef WIDE_BVH
            WideChildren c = wide_children(link, o, inv_d, best.t);
            uint enters = c.enters;
            if (any_hit) {
                // A shadow query visits every entered child, in any
                // order: the first in slot order now, the others
                // stacked.
                link = NO_SHAPE;
                float t_link = 0.0;
                WIDE_TAKE(8u, c.l3, c.t3)
                WIDE_TAKE(4u, c.l2, c.t2)
                WIDE_TAKE(2u, c.l1, c.t1)
                WIDE_TAKE(1u, c.l0, c.t0)
            } else {
                // The entered children sorted by lane 0's entry
                // distance (as the binary step orders its two), the
                // nearest taken now and the others stacked, the
                // farthest deepest.
                const float NOT_ENTERED = 3.4e38;  // above NO_HIT
                float k0 = subgroupShuffle(c.t0, 0u);
                float k1 = subgroupShuffle(c.t1, 0u);
                float k2 = subgroupShuffle(c.t2, 0u);
                float k3 = subgroupShuffle(c.t3, 0u);
                k0 = (enters & 1u) != 0u ? k0 : NOT_ENTERED;
                k1 = (enters & 2u) != 0u ? k1 : NOT_ENTERED;
                k2 = (enters & 4u) != 0u ? k2 : NOT_ENTERED;
                k3 = (enters & 8u) != 0u ? k3 : NOT_ENTERED;
                order_children(k0, c.l0, c.t0, k1, c.l1, c.t1);
                order_children(k2, c.l2, c.t2, k3, c.l3, c.t3);
                order_children(k0, c.l0, c.t0, k2, c.l2, c.t2);
                order_children(k1, c.l1, c.t1, k3, c.l3, c.t3);
                order_children(k1, c.l1, c.t1, k2, c.l2, c.t2);
                uint entered = bitCount(enters);
                WIDE_STACK(entered > 3u, c.l3, c.t3)
                WIDE_STACK(entered > 2u, c.l2, c.t2)
                WIDE_STACK(entered > 1u, c.l1, c.t1)
                link = entered > 0u ? c.l0 : NO_SHAPE;  // none: pop below
            }
#else
            Shared node = read_node(link);
            float t_left = box_entry(o, inv_d, vec3_at(node, CHILD_LO), vec3_at(node, CHILD_HI), best.t);
            float t_right = box_entry(o, inv_d, vec3_at(node, CHILD_WORDS + CHILD_LO),
                                      vec3_at(node, CHILD_WORDS + CHILD_HI), best.t);
            uint left = word(node, CHILD_LINK);
            uint right = word(node, CHILD_WORDS + CHILD_LINK);
            // One butterfly for both children (bit 0: some lane enters the
            // left one, bit 1: the right one). The nearer child goes first
            // as lane 0 sees them, when lane 0 enters both: rays of a packet
            // are alike, and a vote would lengthen every step's critical
            // path by a second butterfly.
            uint enters = or_lanes((t_left != NO_HIT ? 1u : 0u) | (t_right != NO_HIT ? 2u : 0u));
            bool right_first = subgroupShuffle(t_right < t_left ? 1u : 0u, 0u) != 0u;
            bool enters_left = (enters & 1u) != 0u;
            bool enters_right = (enters & 2u) != 0u;
            if (enters_left && enters_right) {
                stack_link[top] = right_first ? left : right;
                stack_t[top] = right_first ? t_left : t_right;
                ++top;
                link = right_first ? right : left;
            } else if (enters_left) {
                link = left;
            } else if (enters_right) {
                link = right;
            } else {
                link = NO_SHAPE;  // pop below
            }
#endif
        } else {
            search_leaf(link, o, d, shear, any_hit, best);
            link = NO_SHAPE;
        }
        if (link == NO_SHAPE) {
            done = true;
            while (top > 0) {
                --top;
                if (packet_any(stack_t[top] <= best.t)) {
                    link = stack_link[top];
                    done = false;
                    break;
                }
            }
        }
    }
}

#endif
