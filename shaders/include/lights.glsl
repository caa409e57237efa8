// What every pipeline shares about lights and the formula's switches:
// specialization constants 0 to 2 and 32 and the light buffer at binding 0. The
// host's side is `raster_layout::SPEC_CONSTANTS` (which `raytrace::layout` starts
// with) and `raster_layout::GpuLight`.
#ifndef LIGHTS_GLSL
#define LIGHTS_GLSL

layout(constant_id = 0) const int LIGHT_COUNT = 1;
layout(constant_id = 1) const bool USE_SPECULAR = true;
layout(constant_id = 2) const bool USE_ATTENUATION = true;
// With USE_ATTENUATION: Il / d^2 (`falloff = "inverse-square"`) instead of
// the lecture's Il / (d + k). An id past both pipelines' own constants.
layout(constant_id = 32) const bool INVERSE_SQUARE = false;

struct PointLight {
    vec4 position;   // xyz: camera-relative position
    vec4 intensity;  // rgb: Il
};

layout(std430, set = 0, binding = 0) readonly buffer LightBuffer {
    PointLight lights[];
};

#endif
