#version 460
#extension GL_GOOGLE_include_directive : require
// Phong shading: the formula once per pixel with the interpolated normal,
// renormalised, at the interpolated position; the surface's colour times
// the interpolated vertex colour (VERTEX_COLOR) and the pattern at the
// interpolated texture coordinates (PATTERN).
#include "raster_interface.glsl"
#include "raster_output.glsl"
#include "lighting.glsl"
#include "raster_surface.glsl"
#include "screen_linear.glsl"
#ifdef PATTERN
#include "pattern.glsl"
#endif

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
#ifdef SCREEN_LINEAR
layout(location = 2) in float in_w;
#define PER_PIXEL(v) ((v) / in_w)
#else
#define PER_PIXEL(v) (v)
#endif
#ifdef VERTEX_COLOR
// The interpolated vertex colour (times w, screen-linearly).
layout(location = 3) in vec3 in_tint;
#endif
#ifdef PATTERN
layout(location = 4) in vec2 in_uv;
#endif
#if defined(VERTEX_COLOR) && defined(PATTERN)
#define SURFACE tinted(draw_surface(), PER_PIXEL(in_tint) * pattern_color(PER_PIXEL(in_uv)))
#elif defined(VERTEX_COLOR)
#define SURFACE tinted(draw_surface(), PER_PIXEL(in_tint))
#elif defined(PATTERN)
#define SURFACE tinted(draw_surface(), pattern_color(PER_PIXEL(in_uv)))
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
    // A triangle seen from behind is lit as its back: the normal negated
    // (docs/lighting-model.md, "Which side is lit").
    N = gl_FrontFacing ? N : -N;
    WRITE_COLOR(shade(P, surface_normal(N), normalize(-P), SURFACE, frame.ambient_k.rgb, frame.ambient_k.w));
}
