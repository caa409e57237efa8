// The ray tracer's subgroup as one packet (raytrace.comp.glsl's opening
// comment says why): a vote over the lanes, and records read once by the
// whole subgroup and handed to every lane by shuffles.
#ifndef RT_PACKET_GLSL
#define RT_PACKET_GLSL

#include "rt_interface.glsl"

// The OR of `v` over the subgroup; every lane must be here. A butterfly of
// shuffles, written out: lavapipe does not unroll a loop over the steps,
// and a loop costs it far more than the shuffles; subgroupAny and
// subgroupOr are scalar loops over the lanes there. Sizes up to 64 (the
// tests on gl_SubgroupSize fold away where the driver knows it).
uint or_lanes(uint v) {
    uint lane = gl_SubgroupInvocationID;
    v |= subgroupShuffle(v, lane ^ 1u);
    if (gl_SubgroupSize > 2u) {
        v |= subgroupShuffle(v, lane ^ 2u);
    }
    if (gl_SubgroupSize > 4u) {
        v |= subgroupShuffle(v, lane ^ 4u);
    }
    if (gl_SubgroupSize > 8u) {
        v |= subgroupShuffle(v, lane ^ 8u);
    }
    if (gl_SubgroupSize > 16u) {
        v |= subgroupShuffle(v, lane ^ 16u);
    }
    if (gl_SubgroupSize > 32u) {
        v |= subgroupShuffle(v, lane ^ 32u);
    }
    return v;
}

bool packet_any(bool b) {
    return or_lanes(b ? 1u : 0u) != 0u;
}

// A record read by the whole subgroup, as quads of words: lane i holds the
// record's quads i and i + S (S = gl_SubgroupSize; the host requires
// 4 <= S <= 64, and no record has more than 8 quads). Every lane must be
// here; the record's index must be the same in all of them. On lavapipe a
// lane's load is a loop over the lanes, each lane's part with its own
// address and a bounds check per word: the loads of four words a lane took
// fewer of those loops than pairs did (the 40k sphere 13.5 % fewer
// instructions; docs/performance.md).
struct Shared {
    uvec4 q0;
    uvec4 q1;
};

// Word `w` of a shared record, in every lane (with `w` a constant and the
// subgroup size known to the driver, one shuffle).
uint word(Shared r, uint w) {
    uint quad = w >> 2;
    uvec4 held = quad / gl_SubgroupSize == 0u ? r.q0 : r.q1;
    return subgroupShuffle(held[w & 3u], quad % gl_SubgroupSize);
}

vec3 vec3_at(Shared r, uint w) {
    return uintBitsToFloat(uvec3(word(r, w), word(r, w + 1u), word(r, w + 2u)));
}

float float_at(Shared r, uint w) {
    return uintBitsToFloat(word(r, w));
}

// read_X(index): record `index` of buffer X, shared (see Shared).
#define SHARED_READER(name, buffer, quads)                                \
    Shared name(uint index) {                                             \
        uint lane = gl_SubgroupInvocationID;                              \
        uint at = index * (quads) + lane;                                 \
        Shared r = Shared(uvec4(0u), uvec4(0u));                          \
        if (lane < (quads)) {                                             \
            r.q0 = buffer[at];                                            \
        }                                                                 \
        if (lane + gl_SubgroupSize < (quads)) {                           \
            r.q1 = buffer[at + gl_SubgroupSize];                          \
        }                                                                 \
        return r;                                                         \
    }

// X_word(index, w): word `w` of record `index`, read by this lane alone.
#define LANE_READER(name, buffer, quads)                                  \
    uint name(uint index, uint w) {                                       \
        return buffer[index * (quads) + (w >> 2)][w & 3u];                \
    }

#ifdef WIDE_BVH
SHARED_READER(read_wide_node, node_quads, WIDE_NODE_QUADS)
#else
SHARED_READER(read_node, node_quads, NODE_QUADS)
#endif
SHARED_READER(read_triangle, triangle_quads, TRI_QUADS)
SHARED_READER(read_sphere, sphere_quads, SPHERE_QUADS)
SHARED_READER(read_plane, plane_quads, PLANE_QUADS)
SHARED_READER(read_box, box_quads, BOX_QUADS)
LANE_READER(triangle_word, triangle_quads, TRI_QUADS)
LANE_READER(sphere_word, sphere_quads, SPHERE_QUADS)
LANE_READER(plane_word, plane_quads, PLANE_QUADS)
LANE_READER(box_word, box_quads, BOX_QUADS)

#endif
