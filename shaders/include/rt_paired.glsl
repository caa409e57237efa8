// Two rays a lane (compiled with PAIRED, over the 4-wide walk): the
// nearest hits of two packets' eye rays found in one walk, each node's and
// triangle's read, the vote over the lanes and the loop's decisions shared
// by both. A lane's two rays are two pixels' (raytrace.comp.glsl), and each
// gets the nearest hit, ties included, that a walk of its own would give:
// a node is entered when either ray of any lane enters it within its own
// limit, and a stacked node is skipped only when neither ray of any lane
// can still find a nearer hit in it (docs/raytracing.md, "Two rays a
// lane"). Where it pays is the device's to say: the host picks this module
// where the driver's registers hold a second ray (gpu::raytrace::pairing).
#ifndef RT_PAIRED_GLSL
#define RT_PAIRED_GLSL

#include "rt_interface.glsl"
#include "rt_ray.glsl"
#include "rt_packet.glsl"
#include "rt_hit_rule.glsl"
#include "rt_primitives.glsl"
#include "rt_bvh.glsl"
#include "rt_search.glsl"

// Two children in the order of their keys, each with both rays' entry
// distances.
void order_pair(inout float ka, inout uint la, inout vec2 ta, inout float kb, inout uint lb, inout vec2 tb) {
    bool swap = kb < ka;
    float k = ka;
    uint l = la;
    vec2 t = ta;
    ka = swap ? kb : ka;
    la = swap ? lb : la;
    ta = swap ? tb : ta;
    kb = swap ? k : kb;
    lb = swap ? l : lb;
    tb = swap ? t : tb;
}

// A leaf against both rays: a triangle read once for the two.
void search_leaf_pair(uint link, vec3 o, vec3 d1, vec3 d2, RayFrame s1, RayFrame s2, inout Hit b1,
                      inout Hit b2) {
    uint first = link & 0x03ffffffu;
    uint end = first + ((link >> 26) & 31u) + 1u;
    if (first < frame.leaf_bases.x) {
        for (uint i = first; i < end; ++i) {
            Shared tri = read_triangle(i);
            vec2 uv;
            float t = triangle_t(s1, tri, uv);
            consider_triangle(t, KIND_TRIANGLE | i, uv, b1);
            t = triangle_t(s2, tri, uv);
            consider_triangle(t, KIND_TRIANGLE | i, uv, b2);
        }
    } else {
        search_leaf_objects(first, end, o, d1, false, b1);
        search_leaf_objects(first, end, o, d2, false, b2);
    }
}

#define PAIR_STACK(cond, child, t) \
    if (cond) {                    \
        stack_link[top] = child;   \
        stack_t[top] = t;          \
        ++top;                     \
    }

// walk_bvh's nearest-hit walk of the 4-wide tree for two rays from `o`.
// The entered children go in the order lane 0 enters them along its first
// ray (its second where the first enters none).
void walk_bvh_pair(vec3 o, vec3 d1, vec3 d2, inout Hit best1, inout Hit best2) {
    uint link = frame.grid.w;
    vec3 inv1 = slab_inverse(d1);
    vec3 inv2 = slab_inverse(d2);
    RayFrame s1 = ray_frame(o, d1);
    RayFrame s2 = ray_frame(o, d2);
    // The wide walk's stack need (wide_bvh::WideBvh::stack_need) bounds it.
    uint stack_link[BVH_STACK_SIZE];
    vec2 stack_t[BVH_STACK_SIZE];
    int top = 0;
    bool done = false;
    while (!done) {
        if ((link & LEAF_BIT) == 0u) {
            Shared node = read_wide_node(link);
            vec4 e1 = wide_entries(node, o, inv1, best1.t);
            vec4 e2 = wide_entries(node, o, inv2, best2.t);
            uint l0 = word(node, CHILD_LINK);
            uint l1 = word(node, CHILD_WORDS + CHILD_LINK);
            uint l2 = word(node, 2u * CHILD_WORDS + CHILD_LINK);
            uint l3 = word(node, 3u * CHILD_WORDS + CHILD_LINK);
            uint enters = or_lanes(entered_bits(e1) | entered_bits(e2));
            enters &= (l0 != NO_SHAPE ? 1u : 0u) | (l1 != NO_SHAPE ? 2u : 0u) | (l2 != NO_SHAPE ? 4u : 0u) |
                      (l3 != NO_SHAPE ? 8u : 0u);
            const float NOT_ENTERED = 3.4e38;  // above NO_HIT
            vec4 key = subgroupShuffle(min(e1, e2), 0u);
            float k0 = (enters & 1u) != 0u ? key.x : NOT_ENTERED;
            float k1 = (enters & 2u) != 0u ? key.y : NOT_ENTERED;
            float k2 = (enters & 4u) != 0u ? key.z : NOT_ENTERED;
            float k3 = (enters & 8u) != 0u ? key.w : NOT_ENTERED;
            vec2 t0 = vec2(e1.x, e2.x);
            vec2 t1 = vec2(e1.y, e2.y);
            vec2 t2 = vec2(e1.z, e2.z);
            vec2 t3 = vec2(e1.w, e2.w);
            order_pair(k0, l0, t0, k1, l1, t1);
            order_pair(k2, l2, t2, k3, l3, t3);
            order_pair(k0, l0, t0, k2, l2, t2);
            order_pair(k1, l1, t1, k3, l3, t3);
            order_pair(k1, l1, t1, k2, l2, t2);
            uint entered = bitCount(enters);
            PAIR_STACK(entered > 3u, l3, t3)
            PAIR_STACK(entered > 2u, l2, t2)
            PAIR_STACK(entered > 1u, l1, t1)
            link = entered > 0u ? l0 : NO_SHAPE;
        } else {
            search_leaf_pair(link, o, d1, d2, s1, s2, best1, best2);
            link = NO_SHAPE;
        }
        if (link == NO_SHAPE) {
            done = true;
            while (top > 0) {
                --top;
                if (packet_any(stack_t[top].x <= best1.t || stack_t[top].y <= best2.t)) {
                    link = stack_link[top];
                    done = false;
                    break;
                }
            }
        }
    }
}

// `nearest` for two rays from `o` at once (uniform control flow).
void nearest_pair(vec3 o, vec3 d1, vec3 d2, bool traces1, bool traces2, out Hit hit1, out Hit hit2) {
    hit1 = no_hit_yet(traces1);
    hit2 = no_hit_yet(traces2);
    consider_listed(o, d1, hit1);
    consider_listed(o, d2, hit2);
    if (HAS_BVH) {
        bool near1 = packet_near_bvh(o, d1, hit1.t);
        bool near2 = packet_near_bvh(o, d2, hit2.t);
        if (near1 || near2) {
            walk_bvh_pair(o, d1, d2, hit1, hit2);
        }
    }
    finish_nearest(o, d1, hit1);
    finish_nearest(o, d2, hit2);
}

#endif
