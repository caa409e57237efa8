// The material of the current draw, from the raster push constants.
#ifndef RASTER_SURFACE_GLSL
#define RASTER_SURFACE_GLSL

#include "lighting.glsl"
Surface draw_surface() {
    return Surface(draw.color_ka.rgb, draw.color_ka.a, draw.kd_ks_p.x, draw.kd_ks_p.y, draw.kd_ks_p.z);
}

// With vertex colours or a pattern (VERTEX_COLOR, PATTERN: variants of
// their own, so a scene without them compiles none of this), the point's
// colour C is the material's times them (docs/lighting-model.md, "Surface
// colour").
#if defined(VERTEX_COLOR) || defined(PATTERN)
Surface tinted(Surface s, vec3 tint) {
    s.color *= tint;
    return s;
}
#endif

#endif
