// The compute kernels' work queue (pbrt-v4's WorkQueue and ForAllQueued
// are the model): subgroups take work items from one atomic counter,
// `next_item` (rt_interface.glsl; the host zeroes it before each
// dispatch), until it runs dry, so the work is shared out as it goes, not
// by workgroup id: lavapipe hands each of its threads a fixed share of the
// workgroups, and a thread that was slower (a busier core, or the share of
// the image with the scene in it) left the others idle at the end. What an
// item is, is the kernel's: a patch of pixels for the ray tracer,
// per-lane runs of photons or pixels for the others.
//
// A kernel's loop:
//
//     for (;;) {
//         TAKE_WORK_ITEM(item, lane);
//         if (item >= item_count) {
//             break;
//         }
//         ... the item's work ...
//     }
#ifndef RT_WORK_QUEUE_GLSL
#define RT_WORK_QUEUE_GLSL

#include "rt_interface.glsl"

// Declares `item` and takes the next item into it: lane 0 takes it, every
// lane gets it. Call in uniform control flow (every lane of the subgroup
// here), with `lane` the subgroup invocation's index. A macro that
// expands in the kernel's own loop, not a function: the ray tracer's main
// keeps the loop's state in its own locals, and its module stays what it
// was before the queue was shared (issue 56 compared the SPIR-V).
#define TAKE_WORK_ITEM(item, lane)             \
    uint item = 0u;                            \
    if ((lane) == 0u) {                        \
        item = atomicAdd(next_item, 1u);       \
    }                                          \
    item = subgroupShuffle(item, 0u)

#endif
