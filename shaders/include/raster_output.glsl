// How a raster fragment stage writes its colour. A multisampled PNG is drawn
// into 16-bit unsigned-normalised samples (8-bit sRGB is not averaged in
// linear light on lavapipe, 16-bit floats draw slower there): the colour is
// written times OUTPUT_SCALE = 1/16, so that samples up to 16 keep their
// value through the resolve and the host multiplies by 16 again
// (gpu::raster::ColorTarget::ScaledUnorm16). Any other target: 1.
layout(constant_id = 6) const float OUTPUT_SCALE = 1.0;

#define WRITE_COLOR(c) out_color = vec4((c) * OUTPUT_SCALE, 1.0)
