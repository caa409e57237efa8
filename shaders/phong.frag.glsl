#version 460
#extension GL_GOOGLE_include_directive : require
// Phong shading: the formula once per pixel with the interpolated normal,
// renormalised, at the interpolated position.
#include "raster_interface.glsl"
#include "lighting.glsl"
#include "raster_surface.glsl"

layout(location = 0) INTERP in vec3 in_position;
layout(location = 1) INTERP in vec3 in_normal;
layout(location = 0) out vec4 out_color;

void main() {
    vec3 P = in_position;
    out_color = vec4(shade(P, unit_or_zero(in_normal), normalize(-P), draw_surface(), frame.ambient_k.rgb, frame.ambient_k.w), 1.0);
}
