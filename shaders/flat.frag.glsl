#version 460
#extension GL_GOOGLE_include_directive : require
// Flat shading: the triangle's colour, computed once per triangle in
// flat.vert.glsl, so every fragment of it has exactly that colour.

#include "raster_output.glsl"

layout(location = 0) flat in vec3 in_color;
layout(location = 0) out vec4 out_color;

void main() {
    WRITE_COLOR(in_color);
}
