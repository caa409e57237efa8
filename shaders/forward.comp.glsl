#version 460
#extension GL_GOOGLE_include_directive : require
// Forward ray tracing: photons from the lights, splatted toward the eye at
// every surface that shows them, exactly as docs/lighting-model.md
// ("Forward: photons from the lights") specifies; its f64 twin is
// src/cpu/forward/. The ray tracer's parts find the hits (the packet walk
// of raytrace.comp.glsl, whose opening comment says why it is shaped so):
// each lane carries one photon, and the subgroup walks the BVH together
// while any lane's photon flies.
//
// Photon i draws every number from its own keys (random_streams.glsl's
// STREAM_PHOTON), so its path is the same whichever lane, subgroup or
// dispatch traces it, and its splats are added in fixed point with 64-bit
// integer atomics: the film's sums are the same bits on every run, at any
// thread count, and over any split of the photons into batches or shards.

#include "rt_kernel.glsl"     // the prelude: interface, lighting, finding and shading hits
#include "rt_photon.glsl"     // one photon's flight and its splats
#include "rt_work_queue.glsl" // the work items, shared out as the work goes

// The batch this dispatch traces (gpu::raytrace::forward::PhotonBatch).
layout(push_constant) uniform PhotonBatch {
    uint first;  // its first photon's index
    uint count;  // its photons
    uint total;  // the render's photons, over which the lights' power is split
    uint unused;
} batch;

// Subgroups take items of PHOTONS_PER_LANE x S photons from the queue.
void main() {
    uint lane = gl_SubgroupInvocationID;
    uint size = gl_SubgroupSize;
    start_photon_invocation();
    uint per_item = PHOTONS_PER_LANE * size;
    uint item_count = (batch.count + per_item - 1u) / per_item;
    for (;;) {
        TAKE_WORK_ITEM(item, lane);
        if (item >= item_count) {
            break;
        }
        for (uint k = 0u; k < PHOTONS_PER_LANE; ++k) {
            uint n = item * per_item + k * size + lane;
            // No early return: a lane past the batch's end takes part in
            // its subgroup's packets with no photon.
            trace_photon(batch.first + n, batch.total, n < batch.count);
        }
    }
    flush_photon_counts();
}
