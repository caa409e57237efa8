#version 460
#extension GL_GOOGLE_include_directive : require
// Phong shading: the formula once per pixel with the interpolated normal,
// renormalised, at the interpolated position.
#include "raster_interface.glsl"
#include "lighting.glsl"
#include "raster_surface.glsl"
#include "screen_linear.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
#ifdef SCREEN_LINEAR
layout(location = 2) in float in_w;
#endif
#ifdef VERTEX_COLOR
// The interpolated vertex colour (times w, screen-linearly).
layout(location = 3) in vec3 in_tint;
#ifdef SCREEN_LINEAR
#define SURFACE tinted(draw_surface(), in_tint / in_w)
#else
#define SURFACE tinted(draw_surface(), in_tint)
#endif
#else
#define SURFACE draw_surface()
#endif
layout(location = 0) out vec4 out_color;

void main() {
#ifdef SCREEN_LINEAR
    vec3 P = in_position / in_w;
    vec3 N = in_normal / in_w;
#else
    vec3 P = in_position;
    vec3 N = in_normal;
#endif
    out_color = vec4(shade(P, surface_normal(N), normalize(-P), SURFACE, frame.ambient_k.rgb, frame.ambient_k.w), 1.0);
}
