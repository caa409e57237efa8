// The prelude every compute kernel (raytrace.comp.glsl, forward.comp.glsl,
// caustics.comp.glsl) starts with, after `#version 460` and the include
// directive's extension: the extensions, the workgroup, the sizes the host
// is built with (kernel_sizes.glsl, which build.rs writes from
// src/gpu/raytrace/kernel_sizes.rs), the interface, the lighting model,
// and the ray tracer's parts that find a ray's nearest hit and shade it.
// A kernel adds what it does with them (the ray tree, a photon's flight,
// the photon map), the work queue (rt_work_queue.glsl) and its main.
//
// Every header under shaders/include/ that a kernel includes compiles when
// included alone after this one, with its kernel's defines (FORWARD for
// the photons' headers, PATHS for the bounces'): each includes what it
// needs (src/gpu/shared/shader_catalog.rs's tests hold them to it).
#ifndef RT_KERNEL_GLSL
#define RT_KERNEL_GLSL

#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_shuffle : require
#ifdef FORWARD
// The photons' film and counts are sums in 64-bit integers.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#endif
#ifdef RAY_QUERY
#extension GL_EXT_ray_query : require
#endif

// WORKGROUP_SIZE invocations (a define build.rs passes with every compute
// kernel's, as a layout qualifier comes before the declarations); how
// many workgroups run does not matter (the kernels take their work from a
// queue, rt_work_queue.glsl).
layout(local_size_x = WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

#include "rt_interface.glsl"
#include "lighting.glsl"
#include "texture.glsl"
#include "kernel_sizes.glsl"  // the sizes the host is built with

// The tracer in the order its parts build on each other:
#include "rt_ray.glsl"         // rays, hit records, the ray counts
#include "rt_packet.glsl"      // the subgroup as a packet: votes, shared record reads
#include "rt_hit_rule.glsl"    // which of two hits is the nearest (the tie rule)
#include "rt_objects.glsl"     // the analytic objects' records, and the listed ones
#include "rt_primitives.glsl"  // ray against sphere, plane, box and triangle
#include "rt_bvh.glsl"         // the packet walk of the BVH, binary or 4-wide
#include "rt_search.glsl"      // nearest hit and shadow query: lists, then BVH (or ray queries)
#ifdef PAIRED
#include "rt_paired.glsl"      // two rays a lane: two eye rays' nearest hits in one walk
#endif
#include "rt_surface.glsl"     // what shading needs at a hit: normal, uv, pattern, tint
#include "rt_shading.glsl"     // materials, offsets, direct light with shadow rays

#endif
