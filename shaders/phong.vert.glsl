#version 460
#extension GL_GOOGLE_include_directive : require
// Phong shading: passes the position and the vertex normal on for
// interpolation; screen-linear with SCREEN_LINEAR (see screen_linear.glsl).
#include "raster_interface.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 0) out vec3 out_position;
layout(location = 1) out vec3 out_normal;
#ifdef SCREEN_LINEAR
layout(location = 2) out float out_w;
#endif
#ifdef VERTEX_COLOR
// The vertex colour, interpolated like the normal (the second vertex
// stream).
layout(location = 2) in vec3 in_tint;
layout(location = 3) out vec3 out_tint;
#endif
#ifdef PATTERN
// The texture coordinates, likewise (the third vertex stream).
layout(location = 3) in vec2 in_uv;
layout(location = 4) out vec2 out_uv;
#endif

void main() {
    gl_Position = draw.clip_from_relative * vec4(in_position, 1.0);
#ifdef SCREEN_LINEAR
    out_position = in_position * gl_Position.w;
    out_normal = in_normal * gl_Position.w;
    out_w = gl_Position.w;
#ifdef VERTEX_COLOR
    out_tint = in_tint * gl_Position.w;
#endif
#ifdef PATTERN
    out_uv = in_uv * gl_Position.w;
#endif
#else
    out_position = in_position;
    out_normal = in_normal;
#ifdef VERTEX_COLOR
    out_tint = in_tint;
#endif
#ifdef PATTERN
    out_uv = in_uv;
#endif
#endif
}
