#version 460
#extension GL_GOOGLE_include_directive : require
// Flat shading: the vertex stage only places the triangle; the colour comes
// from the per-triangle record in flat.frag.glsl.
#include "raster_interface.glsl"

layout(location = 0) in vec3 in_position;

void main() {
    gl_Position = draw.clip_from_relative * vec4(in_position, 1.0);
}
