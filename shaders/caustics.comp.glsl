#version 460
#extension GL_GOOGLE_include_directive : require
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

#include "rt_kernel.glsl"     // the prelude: interface, lighting, finding and shading hits
#include "rt_caustics.glsl"   // the pass's interface, visible points, grid, gathering
#include "rt_work_queue.glsl" // the work items, shared out as the work goes

void main() {
    uint pixel_count = frame.image.x * frame.image.y;
    if (batch.stage == 1u || batch.stage == 3u) {
        // One invocation a pixel, in rows of gl_NumWorkGroups.x groups:
        // no tracing, no packets.
        uint pixel = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * uint(WORKGROUP_SIZE) + gl_GlobalInvocationID.x;
        if (pixel < pixel_count) {
            if (batch.stage == 1u) {
                insert_point(pixel);
            } else {
                update_pixel(pixel);
            }
        }
        return;
    }
    // Subgroups take items of CAUSTIC_PER_LANE x S pixels or photons from
    // the queue.
    uint lane = gl_SubgroupInvocationID;
    uint size = gl_SubgroupSize;
    start_photon_invocation();
    bool points = batch.stage == 0u;
    uint work = points ? pixel_count : batch.count;
    uint per_item = CAUSTIC_PER_LANE * size;
    uint item_count = (work + per_item - 1u) / per_item;
    for (;;) {
        TAKE_WORK_ITEM(item, lane);
        if (item >= item_count) {
            break;
        }
        for (uint k = 0u; k < CAUSTIC_PER_LANE; ++k) {
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
