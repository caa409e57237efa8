#version 460
#extension GL_GOOGLE_include_directive : require
// Gouraud shading: writes the interpolated per-vertex intensity. With
// PATTERN, the pattern at the pixel's interpolated texture coordinates
// times the intensity without its specular part, plus that part.
#include "screen_linear.glsl"
#include "raster_interface.glsl"
#include "raster_output.glsl"
#ifdef PATTERN
#include "pattern.glsl"
#endif

layout(location = 0) in vec3 in_front_intensity;
// The back's, for a triangle seen from behind; read only where some draw
// may show its back (BACK_FACES), so that a scene of closed objects seen
// from outside interpolates one intensity, as before backs were lit.
layout(location = 4) in vec3 in_back_intensity;
#ifdef SCREEN_LINEAR
layout(location = 1) in float in_w;
#endif
#ifdef PATTERN
layout(location = 2) in vec3 in_front_specular;
layout(location = 5) in vec3 in_back_specular;
layout(location = 3) in vec2 in_uv;
#endif
layout(location = 0) out vec4 out_color;

void main() {
    vec3 in_intensity = in_front_intensity;
#ifdef PATTERN
    vec3 in_specular = in_front_specular;
#endif
    if (BACK_FACES) {
        if (!gl_FrontFacing) {
            in_intensity = in_back_intensity;
#ifdef PATTERN
            in_specular = in_back_specular;
#endif
        }
    }
#ifdef PATTERN
#ifdef SCREEN_LINEAR
    vec3 color = pattern_color(in_uv / in_w) * (in_intensity / in_w) + in_specular / in_w;
#else
    vec3 color = pattern_color(in_uv) * in_intensity + in_specular;
#endif
    WRITE_COLOR(color);
#else
#ifdef SCREEN_LINEAR
    WRITE_COLOR(in_intensity / in_w);
#else
    WRITE_COLOR(in_intensity);
#endif
#endif
}
