#version 460
#extension GL_GOOGLE_include_directive : require
// Phong shading: passes the position and the vertex normal on for
// interpolation (INTERP is `smooth` or `noperspective`, set by build.rs).
#include "raster_interface.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 0) INTERP out vec3 out_position;
layout(location = 1) INTERP out vec3 out_normal;

void main() {
    out_position = in_position;
    out_normal = in_normal;
    gl_Position = draw.clip_from_relative * vec4(in_position, 1.0);
}
