#version 460
#extension GL_GOOGLE_include_directive : require
// Gouraud shading: writes the interpolated per-vertex intensity.
#include "screen_linear.glsl"

layout(location = 0) in vec3 in_intensity;
#ifdef SCREEN_LINEAR
layout(location = 1) in float in_w;
#endif
layout(location = 0) out vec4 out_color;

void main() {
#ifdef SCREEN_LINEAR
    out_color = vec4(in_intensity / in_w, 1.0);
#else
    out_color = vec4(in_intensity, 1.0);
#endif
}
