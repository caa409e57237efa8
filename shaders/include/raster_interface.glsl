// The interface between the host and every raster stage: specialization
// constants, descriptor bindings and push constants. The host's side of it is
// src/gpu/raster/layout.rs; tests/cpu/shader_interface.rs checks the two agree
// using naga's reflection of the compiled SPIR-V.
//
// Positions here are camera-relative (world position minus eye, computed in
// double precision on the host), so the eye sits at the origin and far-away
// scenes keep their float precision.
#ifndef RASTER_INTERFACE_GLSL
#define RASTER_INTERFACE_GLSL

// Features a scene does not use are compiled out (chosen per scene on the
// host): constants 0 to 2 and the lights, shared with the ray tracer.
#include "lights.glsl"

// Whether some draw may show its back (src/gpu/raster/cull.rs): where none
// can, Gouraud lights no vertex's back.
layout(constant_id = 5) const bool BACK_FACES = true;

layout(std140, set = 0, binding = 1) uniform FrameUniforms {
    vec4 ambient_k;  // rgb: Ia, w: the constant k of Il / (d + k)
} frame;

#ifdef TEXTURE
// The scene's image textures (gpu::texture_table), read by texture.glsl.
layout(std430, set = 0, binding = 3) readonly buffer TextureRecordBuffer { uvec4 texture_records[]; };
layout(std430, set = 0, binding = 4) readonly buffer TexelBuffer { vec4 texels[]; };
// Where every image has one sampler: its bits (texture.glsl).
layout(constant_id = 3) const bool SAMPLER_FIXED = false;
layout(constant_id = 4) const uint FIXED_SAMPLER = 0u;
#endif

layout(push_constant) uniform DrawConstants {
    mat4 clip_from_relative;  // projection * view rotation
    vec4 color_ka;            // rgb: material colour C, a: ka
    vec4 kd_ks_p;             // x: kd, y: ks, z: p
#ifdef PATTERN
    // The draw's pattern (raster_layout::PatternConstants).
    vec4 checker_a;           // rgb: first colour, w: scale (0: no pattern;
                              // -1 - index: image `index`, its uv transform's
                              // rows in the two xyz)
    vec4 checker_b;           // rgb: second colour
#endif
} draw;

#endif
