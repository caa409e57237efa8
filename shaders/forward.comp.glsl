#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_shuffle : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
// Forward ray tracing: photons from the lights, splatted toward the eye at
// every surface that shows them, exactly as docs/lighting-model.md
// ("Forward: photons from the lights") specifies; its f64 twin is
// src/cpu/forward/. The ray tracer's parts find the hits (the packet walk
// of raytrace.comp.glsl, whose opening comment says why it is shaped so):
// each lane carries one photon, and the subgroup walks the BVH together
// while any lane's photon flies.
//
// Photon i draws every number from pcg4d(i, level, 0, 2), so its path is
// the same whichever lane, subgroup or dispatch traces it, and its splats
// are added in fixed point with 64-bit integer atomics: the film's sums are
// the same bits on every run, at any thread count, and over any split of
// the photons into batches or shards.

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

#include "rt_interface.glsl"
#include "lighting.glsl"
#include "texture.glsl"

// The sizes the host holds the shader to, as in raytrace.comp.glsl.
const int BVH_STACK_SIZE = 64;
const int UNROLLED_SPHERES = 16;
const int UNROLLED_PLANES = 12;
const int UNROLLED_BOXES = 6;
const int UNROLLED_MATERIALS = 8;
// Photons each lane traces per work item (forward::PHOTONS_PER_LANE).
const uint PHOTONS_PER_LANE = 16u;

// The batch this dispatch traces (gpu::raytrace::forward::PhotonBatch).
layout(push_constant) uniform PhotonBatch {
    uint first;  // its first photon's index
    uint count;  // its photons
    uint total;  // the render's photons, over which the lights' power is split
    uint unused;
} batch;

#include "rt_ray.glsl"         // rays, hit records, the ray counts
#include "rt_packet.glsl"      // the subgroup as a packet: votes, shared record reads
#include "rt_hit_rule.glsl"    // which of two hits is the nearest (the tie rule)
#include "rt_objects.glsl"     // the analytic objects' records, and the listed ones
#include "rt_primitives.glsl"  // ray against sphere, plane, box and triangle
#include "rt_bvh.glsl"         // the packet walk of the BVH, binary or 4-wide
#include "rt_search.glsl"      // nearest hit and shadow query
#include "rt_surface.glsl"     // what shading needs at a hit: normal, uv, pattern, tint
#include "rt_shading.glsl"     // materials, offsets
#include "rt_bounce.glsl"      // random numbers, cosine-weighted directions
#include "rt_children.glsl"    // a hit's reflected and refracted directions
#include "rt_photon.glsl"      // one photon's flight and its splats

void main() {
    // Subgroups take items of PHOTONS_PER_LANE x S photons from a queue
    // (one atomic counter) until it runs dry, as the ray tracer takes its
    // pixels (raytrace.comp.glsl says why).
    uint lane = gl_SubgroupInvocationID;
    uint size = gl_SubgroupSize;
    for (int k = 0; k < 4; ++k) {
        counted_photons[k] = 0ul;
    }
    read_listed_objects();
    if (MATERIALS_LISTED) {
        read_listed_materials();
    }
    uint per_item = PHOTONS_PER_LANE * size;
    uint item_count = (batch.count + per_item - 1u) / per_item;
    for (;;) {
        uint item = 0u;
        if (lane == 0u) {
            item = atomicAdd(next_item, 1u);
        }
        item = subgroupShuffle(item, 0u);
        if (item >= item_count) {
            break;
        }
        for (uint k = 0u; k < PHOTONS_PER_LANE; ++k) {
            uint n = item * per_item + k * size + lane;
            // No early return: a lane past the batch's end takes part in
            // its subgroup's packets with no photon.
            trace_photon(batch.first + n, n < batch.count);
        }
    }
    flush_photon_counts();
}
