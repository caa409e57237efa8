#version 460
#extension GL_GOOGLE_include_directive : require
// Flat shading: the formula once per triangle, at its centroid with its
// geometric normal, in the vertex stage. Every triangle has a first
// (provoking) vertex of its own whose index is the triangle's record
// (src/gpu/raster/flat.rs); its value colours the whole triangle, and the
// fragment stage only writes it.
#include "raster_interface.glsl"
#include "lighting.glsl"
#include "raster_surface.glsl"

// One record per flat vertex, computed on the host: the faces' in face
// order, then copies for the vertices that provoke no face.
struct Face {
    vec4 center;     // xyz: camera-relative centroid
    vec4 normal;     // xyz: unit geometric normal
};

layout(std430, set = 0, binding = 2) readonly buffer FaceBuffer {
    Face faces[];
};

layout(location = 0) in vec3 in_position;
#ifdef VERTEX_COLOR
// The face's colour: the mean of its corners' vertex colours, computed on
// the host like the centroid (the second vertex stream).
layout(location = 1) in vec3 in_tint;
#define SURFACE tinted(draw_surface(), in_tint)
#else
#define SURFACE draw_surface()
#endif
layout(location = 0) flat out vec3 out_color;

void main() {
    // Fields are read one by one: naga's SPIR-V reader lacks OpCopyLogical,
    // which a whole-struct copy out of the std430 buffer would emit.
    uint face = uint(gl_VertexIndex);
    vec3 P = faces[face].center.xyz;
    vec3 N = faces[face].normal.xyz;
    // A face seen from behind is lit as its back (docs/lighting-model.md,
    // "Which side is lit").
    N = dot(N, P) > 0.0 ? -N : N;
    out_color = shade(P, N, normalize(-P), SURFACE, frame.ambient_k.rgb, frame.ambient_k.w);
    gl_Position = draw.clip_from_relative * vec4(in_position, 1.0);
}
