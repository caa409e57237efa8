#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_shuffle : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
// Caustics from a progressive photon map (SPPM), exactly as
// docs/lighting-model.md ("Caustics: light the eye's rays cannot find")
// specifies; its f64 twin is src/cpu/caustics/. One pass of the map is
// four dispatches of this module, told apart by `pass_info.stage`:
//
// 0. visible points: each pixel's eye path through mirrors and glass to
//    the diffuse surface it stops on (a packet walk, as the ray tracer's);
// 1. the grid: each visible point put into the hashed cells its radius
//    overlaps, as a linked list per bucket;
// 2. photons: the pass's caustic photons traced from the lights (the
//    forward tracer's flights, rt_photon.glsl), each landing added to the
//    visible points within their radius, in fixed point with 64-bit
//    atomics, so that the sums do not depend on the order of the lanes;
// 3. the update: each pixel's radius, count and flux by SPPM's rule, in a
//    fixed order per pixel, then the pass's sums and grid cleared.
//
// So a pass's image is the same bits on every run. The grid only narrows
// the search: a photon is gathered by every visible point within its
// radius, whatever the hash.

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
// Photons or pixels each lane traces per work item
// (gpu::raytrace::caustics::PER_LANE).
const uint PER_LANE = 16u;

// The dispatch (gpu::raytrace::caustics::CausticPass).
layout(push_constant) uniform CausticPass {
    uint first;            // the pass's first photon
    uint count;            // its photons
    uint total;            // photons per pass, over which the lights' power is split
    uint stage;            // 0 visible points, 1 grid, 2 photons, 3 update
    uint pass;             // the pass's number, which keys the eye paths' numbers
    uint buckets;          // the grid's hash buckets
    float initial_radius;  // in pixel footprints
    float alpha;           // SPPM's share of new photons kept
} batch;

// Each pixel's visible point this pass, three quads: xyz its position and
// w its radius (negative: none this pass); xyz the normal on the side it
// faces; xyz its weight, the eye path's weights times kd C.
layout(std430, set = 1, binding = 0) buffer VisiblePointBuffer { vec4 points[]; };
// Each pixel's state over the passes, two quads: rgb its flux so far and
// w its count of photons kept; x its radius (0 until it has had a point).
layout(std430, set = 1, binding = 1) buffer PixelStateBuffer { vec4 states[]; };
// The grid: the widest radius of the pass (as the bits of a float, which
// order as the floats do for radii of 0 or more), the nodes used, and
// each bucket's first node.
layout(std430, set = 1, binding = 2) buffer GridBuffer {
    uint grid_widest;
    uint grid_nodes;
    uint grid_unused0;
    uint grid_unused1;
    uint heads[];
};
// A bucket's list: x a pixel, y the next node.
layout(std430, set = 1, binding = 3) buffer GridNodeBuffer { uvec2 nodes[]; };
// Each pixel's photons gathered this pass.
layout(std430, set = 1, binding = 4) buffer FoundBuffer { uint found[]; };

const uint NO_NODE = 0xffffffffu;

#include "rt_ray.glsl"         // rays, hit records, the ray counts
#include "rt_packet.glsl"      // the subgroup as a packet: votes, shared record reads
#include "rt_hit_rule.glsl"    // which of two hits is the nearest (the tie rule)
#include "rt_objects.glsl"     // the analytic objects' records, and the listed ones
#include "rt_primitives.glsl"  // ray against sphere, plane, box and triangle
#include "rt_bvh.glsl"         // the packet walk of the BVH, binary or 4-wide
#include "rt_search.glsl"      // nearest hit and shadow query
#include "rt_surface.glsl"     // what shading needs at a hit: normal, uv, pattern, tint
#include "rt_shading.glsl"     // materials, offsets
#include "rt_bounce.glsl"      // random numbers
#include "rt_children.glsl"    // a hit's reflected and refracted directions
#include "rt_photon.glsl"      // a photon's flight from its light
#include "rt_caustics.glsl"    // the visible points, the grid, the gathering

void main() {
    uint pixel_count = frame.image.x * frame.image.y;
    if (batch.stage == 1u || batch.stage == 3u) {
        // One invocation a pixel, in rows of gl_NumWorkGroups.x groups:
        // no tracing, no packets.
        uint pixel = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x;
        if (pixel < pixel_count) {
            if (batch.stage == 1u) {
                insert_point(pixel);
            } else {
                update_pixel(pixel);
            }
        }
        return;
    }
    // Subgroups take items of PER_LANE x S pixels or photons from a queue
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
    bool points = batch.stage == 0u;
    uint work = points ? pixel_count : batch.count;
    uint per_item = PER_LANE * size;
    uint item_count = (work + per_item - 1u) / per_item;
    for (;;) {
        uint item = 0u;
        if (lane == 0u) {
            item = atomicAdd(next_item, 1u);
        }
        item = subgroupShuffle(item, 0u);
        if (item >= item_count) {
            break;
        }
        for (uint k = 0u; k < PER_LANE; ++k) {
            uint n = item * per_item + k * size + lane;
            // No early return: a lane past the end takes part in its
            // subgroup's packets with no work.
            if (points) {
                trace_visible_point(n, n < work);
            } else {
                trace_caustic_photon(batch.first + n, n < work);
            }
        }
    }
    flush_photon_counts();
}
