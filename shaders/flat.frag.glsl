#version 460
// Flat shading: the triangle's colour, computed once per triangle in
// flat.vert.glsl, so every fragment of it has exactly that colour.

layout(location = 0) flat in vec3 in_color;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(in_color, 1.0);
}
