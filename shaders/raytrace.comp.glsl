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
    uint width = frame.image.x;
    uint height = frame.image.y;
    for (int k = 0; k < 5; ++k) {
        local_counts[k] = 0u;
    }
#ifndef RAY_QUERY
    read_listed_objects();
#endif
    if (MATERIALS_LISTED) {
        read_listed_materials();
    }
    // 1..1024 on the host; at least 1 here, as the sample loop runs once.
    uint samples = max(frame.image.z, 1u);
    float kx = float(frame.grid.x);
    // The camera's divisions, once per invocation: per pixel they were a
    // chain of dependent divisions at the start of every ray, about a tenth
    // of a small scene's time (profiled on assets/rt-mesh.toml). Products
    // with reciprocals round differently from the quotients by an ulp at
    // most, as the f32 quotients already differ from the reference's f64.
    float inv_kx = 1.0 / kx;
    float inv_ky = 1.0 / float(frame.grid.y);
    vec2 ndc_per_pixel = vec2(2.0 / float(width), 2.0 / float(height));
    float inv_focal = 1.0 / frame.right_focal.w;
    vec3 right_per_ndc = frame.right_focal.xyz * (frame.up_aspect.w * inv_focal);
    vec3 up_per_ndc = frame.up_aspect.xyz * inv_focal;
    uint items_across = (width + ITEM_WIDTH - 1u) / ITEM_WIDTH;
    uint item_count = items_across * ((height + size - 1u) / size);
    for (;;) {
        TAKE_WORK_ITEM(item, lane);
        if (item >= item_count) {
            break;
        }
        uvec2 origin = uvec2(item % items_across * ITEM_WIDTH, item / items_across * size);
#ifdef PAIRED
        // Two packets at a time: packet b's pixel and packet b + 1's are
        // this lane's two rays, their eye rays' nearest hits found in one
        // walk, then each one's ray tree in turn (a loop the driver does
        // not unroll, its count read at run time, so that the tree is
        // compiled once).
        uint trees = 2u + (frame.image.w >> 31);  // the depth is below 2^31
        for (uint b = 0u; b < ITEM_PACKETS; b += 2u) {
            uvec2 pixel1 = origin + uvec2((b & 3u) * 4u, (b >> 2) * rows_per_patch) + in_patch;
            uvec2 pixel2 = origin + uvec2(((b + 1u) & 3u) * 4u, ((b + 1u) >> 2) * rows_per_patch) + in_patch;
            bool on1 = pixel1.x < width && pixel1.y < height;
            bool on2 = pixel2.x < width && pixel2.y < height;
            vec3 sum1 = vec3(0.0);
            vec3 sum2 = vec3(0.0);
            for (uint i = 0u;;) {
                vec2 cell = grid_cell(i, kx, inv_kx, inv_ky);
                vec2 ndc1 = (vec2(pixel1) + cell) * ndc_per_pixel - 1.0;
                vec2 ndc2 = (vec2(pixel2) + cell) * ndc_per_pixel - 1.0;
                vec3 dir1 = frame.forward_cutoff.xyz + right_per_ndc * ndc1.x - up_per_ndc * ndc1.y;
                vec3 dir2 = frame.forward_cutoff.xyz + right_per_ndc * ndc2.x - up_per_ndc * ndc2.y;
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
                if (++i >= samples) {
                    break;
                }
            }
            if (on1) {
                pixels[pixel1.y * width + pixel1.x] = vec4(sum1 / float(samples), 1.0);
            }
            if (on2) {
                pixels[pixel2.y * width + pixel2.x] = vec4(sum2 / float(samples), 1.0);
            }
        }
#else
        for (uint b = 0u; b < ITEM_PACKETS; ++b) {
            uvec2 pixel = origin + uvec2((b & 3u) * 4u, (b >> 2) * rows_per_patch) + in_patch;
            // No early return: lanes off the image still join the packets.
            bool on_image = pixel.x < width && pixel.y < height;
#ifdef PATHS
            uvec2 sums[3] = uvec2[3](uvec2(0u), uvec2(0u), uvec2(0u));
#else
            vec3 sum = vec3(0.0);
#endif
            // At least one sample (the host keeps a PATHS range non-empty),
            // so the test ends the loop rather than opening it: tested
            // first, the small scenes took 1.1x to 1.3x the time on
            // lavapipe (24 to 50 alternated runs), the images the same.
#ifdef PATHS
            uint pixel_index = pixel.y * width + pixel.x;
            for (uint i = sample_range.first;;) {
                // A point of the progressive sequence: any prefix covers the pixel.
                vec2 cell = pixel_sample(pixel_index, i);
#else
            for (uint i = 0u;;) {
                vec2 cell = grid_cell(i, kx, inv_kx, inv_ky);
#endif
                vec2 ndc = (vec2(pixel) + cell) * ndc_per_pixel - 1.0;
                vec3 dir = frame.forward_cutoff.xyz + right_per_ndc * ndc.x - up_per_ndc * ndc.y;
#ifdef PATHS
                sample_sampler = start_pixel_sample(pixel_index, i);
                vec3 value = trace_sample(dir * inversesqrt(dot(dir, dir)), on_image);
                add_sample(sums, value / float(samples));
                i += max(sample_range.step, 1u);
                if (i >= sample_range.end) {
                    break;
                }
            }
            if (on_image) {
                add_to_pixel(pixel.y * width + pixel.x, sums);
            }
#else
                sum += trace_sample(dir * inversesqrt(dot(dir, dir)), on_image);
                if (++i >= samples) {
                    break;
                }
            }
            if (on_image) {
                pixels[pixel.y * width + pixel.x] = vec4(sum / float(samples), 1.0);
            }
#endif
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
