#version 460
#extension GL_GOOGLE_include_directive : require
// Gouraud shading: the formula once per vertex; the rasterizer interpolates
// the intensity. With SCREEN_LINEAR (set by build.rs for
// `interpolation = "screen"`) the interpolation is screen-linear, made from
// perspective-correct varyings as include/screen_linear.glsl explains.
#include "raster_interface.glsl"
#include "lighting.glsl"
#include "raster_surface.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
#ifdef VERTEX_COLOR
// The vertex's own colour enters the formula where it runs, at the vertex
// (the second vertex stream).
layout(location = 2) in vec3 in_tint;
#define SURFACE tinted(draw_surface(), in_tint)
#else
#define SURFACE draw_surface()
#endif
layout(location = 0) out vec3 out_intensity;
#ifdef SCREEN_LINEAR
layout(location = 1) out float out_w;
#endif

void main() {
    vec3 P = in_position;
    vec3 intensity = shade(P, surface_normal(in_normal), normalize(-P), SURFACE, frame.ambient_k.rgb, frame.ambient_k.w);
    gl_Position = draw.clip_from_relative * vec4(P, 1.0);
#ifdef SCREEN_LINEAR
    out_intensity = intensity * gl_Position.w;
    out_w = gl_Position.w;
#else
    out_intensity = intensity;
#endif
}
