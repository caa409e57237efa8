// How a raster fragment stage writes its colour.
//
// Multisampled and shaded once per pixel, the inputs at a pixel centre
// outside the triangle are extrapolated (docs/lighting-model.md, "Samples
// per pixel"), and Gouraud's intensities or a vertex colour can go below 0
// there: a colour below 0 counts as 0 (AT_LEAST_ZERO; NaN is kept, to be
// counted). Inside a triangle no built-in colour is below 0.
//
// A multisampled PNG is drawn into 16-bit unsigned-normalised samples
// (8-bit sRGB is not averaged in linear light on lavapipe, 16-bit floats
// draw slower there): the colour is written times OUTPUT_SCALE = 1/16, so
// that samples up to 16 keep their value through the resolve, and the host
// multiplies by 16 again (gpu::raster::ColorTarget::ScaledUnorm16). Any
// other target: 1.
#ifndef RASTER_OUTPUT_GLSL
#define RASTER_OUTPUT_GLSL
layout(constant_id = 6) const float OUTPUT_SCALE = 1.0;
layout(constant_id = 7) const bool AT_LEAST_ZERO = false;

vec3 written(vec3 c) {
    return (AT_LEAST_ZERO ? mix(c, vec3(0.0), lessThan(c, vec3(0.0))) : c) * OUTPUT_SCALE;
}

#define WRITE_COLOR(c) out_color = vec4(written(c), 1.0)

#endif
