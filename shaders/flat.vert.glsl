#version 460
#extension GL_GOOGLE_include_directive : require
// Flat shading: the formula once per triangle, at its centroid with its
// geometric normal, in the vertex stage. Flat draws are not indexed: every
// triangle has three vertices of its own, in the order of the per-triangle
// records, so vertex v belongs to record v / 3. The value of the triangle's
// first (provoking) vertex colours the whole triangle; the fragment stage
// only writes it.
#include "raster_interface.glsl"
#include "lighting.glsl"
#include "raster_surface.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 0) flat out vec3 out_color;

void main() {
    // Fields are read one by one: naga's SPIR-V reader lacks OpCopyLogical,
    // which a whole-struct copy out of the std430 buffer would emit.
    uint face = uint(gl_VertexIndex) / 3u;
    vec3 P = faces[face].center.xyz;
    vec3 N = faces[face].normal.xyz;
    out_color = shade(P, N, normalize(-P), draw_surface(), frame.ambient_k.rgb, frame.ambient_k.w);
    gl_Position = draw.clip_from_relative * vec4(in_position, 1.0);
}
