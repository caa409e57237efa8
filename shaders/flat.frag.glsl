#version 460
#extension GL_GOOGLE_include_directive : require
// Flat shading: the formula once per triangle, at its centroid with its
// geometric normal. Every fragment of a triangle reads the same record and
// computes the same value, so a triangle has exactly one colour.
#include "raster_interface.glsl"
#include "lighting.glsl"
#include "raster_surface.glsl"

layout(location = 0) out vec4 out_color;

void main() {
    // Fields are read one by one: naga's SPIR-V reader lacks OpCopyLogical,
    // which a whole-struct copy out of the std430 buffer would emit.
    uint face = draw.face_offset + uint(gl_PrimitiveID);
    vec3 P = faces[face].center.xyz;
    vec3 N = faces[face].normal.xyz;
    out_color = vec4(shade(P, N, normalize(-P), draw_surface(), frame.ambient_k.rgb, frame.ambient_k.w), 1.0);
}
