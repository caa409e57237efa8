#version 460
// Gouraud shading: writes the interpolated per-vertex intensity.

layout(location = 0) INTERP in vec3 in_intensity;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(in_intensity, 1.0);
}
