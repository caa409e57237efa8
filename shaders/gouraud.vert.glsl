#version 460
#extension GL_GOOGLE_include_directive : require
// Gouraud shading: the formula once per vertex; the rasterizer interpolates
// the intensity (INTERP is `smooth` or `noperspective`, set by build.rs).
#include "raster_interface.glsl"
#include "lighting.glsl"
#include "raster_surface.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 0) INTERP out vec3 out_intensity;

void main() {
    vec3 P = in_position;
    out_intensity = shade(P, unit_or_zero(in_normal), normalize(-P), draw_surface(), frame.ambient_k.rgb, frame.ambient_k.w);
    gl_Position = draw.clip_from_relative * vec4(P, 1.0);
}
