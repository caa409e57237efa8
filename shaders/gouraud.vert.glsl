#version 460
#extension GL_GOOGLE_include_directive : require
// Gouraud shading: the formula once per vertex; the rasterizer interpolates
// the intensity. With SCREEN_LINEAR (set by build.rs for
// `interpolation = "screen"`) the interpolation is screen-linear, made from
// perspective-correct varyings as include/screen_linear.glsl explains.
// With PATTERN the pattern is applied per pixel (gouraud.frag.glsl) to the
// interpolated intensity without its specular part, which goes apart.
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
// The same for the triangle's back, lit with the normal negated; the
// fragment stage takes the side it sees (docs/lighting-model.md, "Which
// side is lit").
layout(location = 4) out vec3 out_back_intensity;
#ifdef SCREEN_LINEAR
layout(location = 1) out float out_w;
#endif
#ifdef PATTERN
layout(location = 3) in vec2 in_uv;
layout(location = 2) out vec3 out_specular;
layout(location = 3) out vec2 out_uv;
layout(location = 5) out vec3 out_back_specular;
#endif

void main() {
    vec3 P = in_position;
#ifdef PATTERN
    // The formula without its specular term (ks = 0), which the pattern
    // multiplies per pixel, and the specular term alone (a black surface).
    Surface unlit_specular = SURFACE;
    unlit_specular.ks = 0.0;
    Surface black = SURFACE;
    black.color = vec3(0.0);
    vec3 N = surface_normal(in_normal);
    vec3 intensity = shade(P, N, normalize(-P), unlit_specular, frame.ambient_k.rgb, frame.ambient_k.w);
    vec3 specular = shade(P, N, normalize(-P), black, frame.ambient_k.rgb, frame.ambient_k.w);
    vec3 back_intensity = intensity;
    vec3 back_specular = specular;
    if (BACK_FACES) {
        back_intensity = shade(P, -N, normalize(-P), unlit_specular, frame.ambient_k.rgb, frame.ambient_k.w);
        back_specular = shade(P, -N, normalize(-P), black, frame.ambient_k.rgb, frame.ambient_k.w);
    }
#else
    vec3 N = surface_normal(in_normal);
    vec3 intensity = shade(P, N, normalize(-P), SURFACE, frame.ambient_k.rgb, frame.ambient_k.w);
    vec3 back_intensity = intensity;
    if (BACK_FACES) {
        back_intensity = shade(P, -N, normalize(-P), SURFACE, frame.ambient_k.rgb, frame.ambient_k.w);
    }
#endif
    gl_Position = draw.clip_from_relative * vec4(P, 1.0);
#ifdef SCREEN_LINEAR
    out_intensity = intensity * gl_Position.w;
    out_back_intensity = back_intensity * gl_Position.w;
    out_w = gl_Position.w;
#ifdef PATTERN
    out_specular = specular * gl_Position.w;
    out_back_specular = back_specular * gl_Position.w;
    out_uv = in_uv * gl_Position.w;
#endif
#else
    out_intensity = intensity;
    out_back_intensity = back_intensity;
#ifdef PATTERN
    out_specular = specular;
    out_back_specular = back_specular;
    out_uv = in_uv;
#endif
#endif
}
