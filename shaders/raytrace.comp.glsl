#version 460
#extension GL_GOOGLE_include_directive : require
// Backward (Whitted) ray tracing, exactly as docs/raytracing.md specifies
// (its CPU twin is src/cpu/raytrace/): stratified samples, nearest hits
// with the object-order tie rule, shadow rays, reflection and refraction
// with total internal reflection.
//
// Shaped for lavapipe, which runs a subgroup's 8 invocations in the lanes
// of one SIMD register: a branch costs what the union of its lanes' paths
// costs, and a buffer read at an index that differs between lanes costs a
// scalar load per lane and 4-byte component (docs/raytracing.md, "Why the
// shader is shaped this way"). So a subgroup's rays walk the BVH together,
// as one packet: each lane reads one 8-byte piece of a node or triangle and
// shuffles hand the pieces to every lane. Whatever only the nearest hit
// needs (normals, material) is read once, per lane, after the search.
//
// Packets need every lane of the subgroup present wherever a shuffle runs:
// the walk, and every call that leads to one, is in uniform control flow.
// A lane with nothing to trace (a pixel off the image, a ray tree that has
// ended, a light behind the surface) takes part with a negative distance
// limit, which no box or primitive passes.

// The prelude (extensions, workgroup, sizes, interface, and the parts
// that find and shade a ray's hits), then the rest in the order the parts
// build on each other:
#include "rt_kernel.glsl"
#ifdef PATHS
#include "random_streams.glsl" // the named random streams, and a sampler of them
#include "rt_bounce.glsl"      // diffuse bounces: their numbers, directions
#include "rt_pixel_samples.glsl" // where a pixel's samples look: a progressive sequence
#include "rt_sample_sums.glsl" // samples summed in fixed point, as films are
#endif
#include "rt_children.glsl"    // a hit's reflected and refracted rays
#include "rt_ray_tree.glsl"    // one sample's reflection and refraction tree
#include "rt_work_queue.glsl"  // the work items, shared out as the work goes

// Sample i's cell of the Whitted tracer's grid: row i / kx and column
// i % kx, in floats (exact: (i + 0.5) / kx is 0.5 / kx from an integer or
// more).
vec2 grid_cell(uint i, float kx, float inv_kx, float inv_ky) {
    float row = floor((float(i) + 0.5) * inv_kx);
    float column = float(i) - row * kx;
    return vec2(column + 0.5, row + 0.5) * vec2(inv_kx, inv_ky);
}

// What turns a pixel and a point in it into an eye ray's direction, worked
// out once per invocation: per pixel they were a chain of dependent
// divisions at the start of every ray, about a tenth of a small scene's
// time (profiled on assets/rt-mesh.toml). Products with reciprocals round
// differently from the quotients by an ulp at most, as the f32 quotients
// already differ from the reference's f64.
struct Camera {
    float kx;
    float inv_kx;
    float inv_ky;
    vec2 ndc_per_pixel;
    vec3 right_per_ndc;
    vec3 up_per_ndc;
    // 1..1024 on the host; at least 1 here, as the sample loop runs once.
    uint samples;
};

Camera camera() {
    float kx = float(frame.grid.x);
    float inv_focal = 1.0 / frame.right_focal.w;
    return Camera(kx, 1.0 / kx, 1.0 / float(frame.grid.y),
                  vec2(2.0 / float(frame.image.x), 2.0 / float(frame.image.y)),
                  frame.right_focal.xyz * (frame.up_aspect.w * inv_focal), frame.up_aspect.xyz * inv_focal,
                  max(frame.image.z, 1u));
}

// The eye ray's direction (not yet of unit length) through `cell` of `pixel`.
vec3 eye_direction(Camera c, uvec2 pixel, vec2 cell) {
    vec2 ndc = (vec2(pixel) + cell) * c.ndc_per_pixel - 1.0;
    return frame.forward_cutoff.xyz + c.right_per_ndc * ndc.x - c.up_per_ndc * ndc.y;
}

#ifdef PAIRED
// Two packets' pixels at once: `pixel1` and `pixel2` are this lane's two
// rays, their eye rays' nearest hits found in one walk, then each one's
// ray tree in turn, in a loop of `trees` (2, read at run time so that the
// driver does not unroll it and compiles the tree once).
void trace_pixel_pair(Camera c, uvec2 pixel1, uvec2 pixel2, uint trees) {
    uint width = frame.image.x;
    bool on1 = pixel1.x < width && pixel1.y < frame.image.y;
    bool on2 = pixel2.x < width && pixel2.y < frame.image.y;
    vec3 sum1 = vec3(0.0);
    vec3 sum2 = vec3(0.0);
    for (uint i = 0u;;) {
        vec2 cell = grid_cell(i, c.kx, c.inv_kx, c.inv_ky);
        vec3 dir1 = eye_direction(c, pixel1, cell);
        vec3 dir2 = eye_direction(c, pixel2, cell);
        dir1 *= inversesqrt(dot(dir1, dir1));
        dir2 *= inversesqrt(dot(dir2, dir2));
        Hit hit1, hit2;
        nearest_pair(vec3(0.0), dir1, dir2, on1, on2, hit1, hit2);
        for (uint k = 0u; k < trees; ++k) {
            // `k` is the same in every lane: uniform control flow.
            vec3 dir = dir1;
            bool on = on1;
            Hit hit = hit1;
            if (k == 1u) {
                dir = dir2;
                on = on2;
                hit = hit2;
            }
            vec3 value = trace_sample(dir, on, hit);
            if (k == 1u) {
                sum2 += value;
            } else {
                sum1 += value;
            }
        }
        if (++i >= c.samples) {
            break;
        }
    }
    if (on1) {
        pixels[pixel1.y * width + pixel1.x] = vec4(sum1 / float(c.samples), 1.0);
    }
    if (on2) {
        pixels[pixel2.y * width + pixel2.x] = vec4(sum2 / float(c.samples), 1.0);
    }
}
#else
// One pixel's samples, this lane's part of a packet. No early return:
// lanes off the image still join the packets.
void trace_pixel(Camera c, uvec2 pixel) {
    uint width = frame.image.x;
    bool on_image = pixel.x < width && pixel.y < frame.image.y;
#ifdef PATHS
    uvec2 sums[3] = uvec2[3](uvec2(0u), uvec2(0u), uvec2(0u));
#else
    vec3 sum = vec3(0.0);
#endif
    // At least one sample (the host keeps a PATHS range non-empty), so the
    // test ends the loop rather than opening it: tested first, the small
    // scenes took 1.1x to 1.3x the time on lavapipe (24 to 50 alternated
    // runs), the images the same.
#ifdef PATHS
    uint pixel_index = pixel.y * width + pixel.x;
    for (uint i = sample_range.first;;) {
        // A point of the progressive sequence: any prefix covers the pixel.
        vec3 dir = eye_direction(c, pixel, pixel_sample(pixel_index, i));
        sample_sampler = start_pixel_sample(pixel_index, i);
        vec3 value = trace_sample(dir * inversesqrt(dot(dir, dir)), on_image);
        add_sample(sums, value / float(c.samples));
        i += max(sample_range.step, 1u);
        if (i >= sample_range.end) {
            break;
        }
    }
    if (on_image) {
        add_to_pixel(pixel.y * width + pixel.x, sums);
    }
#else
    for (uint i = 0u;;) {
        vec3 dir = eye_direction(c, pixel, grid_cell(i, c.kx, c.inv_kx, c.inv_ky));
        sum += trace_sample(dir * inversesqrt(dot(dir, dir)), on_image);
        if (++i >= c.samples) {
            break;
        }
    }
    if (on_image) {
        pixels[pixel.y * width + pixel.x] = vec4(sum / float(c.samples), 1.0);
    }
#endif
}
#endif

// This lane's pixel in packet `b` of the work item at `origin`: the
// packets are patches of 4 x `rows_per_patch` pixels, four across.
uvec2 packet_pixel(uvec2 origin, uint b, uint rows_per_patch, uvec2 in_patch) {
    return origin + uvec2((b & 3u) * 4u, (b >> 2) * rows_per_patch) + in_patch;
}

// Subgroups take work items from the queue (rt_work_queue.glsl says why).
// An item is 16 packets, each packet a 4 x (S/4) patch of
// pixels for a subgroup of S lanes (4 x 2 on lavapipe): 16 x S pixels,
// in rows of items from the top. Each lane's colour depends on its own
// ray alone (see walk_bvh), so which subgroup traces a pixel, and with
// which neighbours, leaves the image as it is.
void main() {
    uint lane = gl_SubgroupInvocationID;
    uint size = gl_SubgroupSize;
    uvec2 in_patch = uvec2(lane & 3u, lane >> 2);
    uint rows_per_patch = size >> 2;
    for (int k = 0; k < 5; ++k) {
        local_counts[k] = 0u;
    }
#ifndef RAY_QUERY
    read_listed_objects();
#endif
    if (MATERIALS_LISTED) {
        read_listed_materials();
    }
    Camera c = camera();
    uint items_across = (frame.image.x + ITEM_WIDTH - 1u) / ITEM_WIDTH;
    uint item_count = items_across * ((frame.image.y + size - 1u) / size);
#ifdef PAIRED
    uint trees = 2u + (frame.image.w >> 31);  // the depth is below 2^31
#endif
    for (;;) {
        TAKE_WORK_ITEM(item, lane);
        if (item >= item_count) {
            break;
        }
        uvec2 origin = uvec2(item % items_across * ITEM_WIDTH, item / items_across * size);
#ifdef PAIRED
        for (uint b = 0u; b < ITEM_PACKETS; b += 2u) {
            uvec2 pixel1 = packet_pixel(origin, b, rows_per_patch, in_patch);
            uvec2 pixel2 = packet_pixel(origin, b + 1u, rows_per_patch, in_patch);
            trace_pixel_pair(c, pixel1, pixel2, trees);
        }
#else
        for (uint b = 0u; b < ITEM_PACKETS; ++b) {
            trace_pixel(c, packet_pixel(origin, b, rows_per_patch, in_patch));
        }
#endif
    }
    if (COUNT_RAYS) {
        for (int k = 0; k < 5; ++k) {
            if (local_counts[k] > 0u) {
                atomicAdd(counters[k], local_counts[k]);
            }
        }
        atomicMax(counters[5], uint(deepest));
    }
}
