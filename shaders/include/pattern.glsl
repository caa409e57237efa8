// The draw's pattern at texture coordinates `uv` (docs/lighting-model.md,
// "Surface colour"): a checkerboard whose cell (floor(scale u),
// floor(scale v)) has the first colour where the two add up to an even
// number; 1 for a material without a pattern. Its CPU twin is
// `Pattern::checker_at` (src/scene/model.rs). With TEXTURE, a pattern may
// be an image instead, read at the level of detail of the pixel's quad
// (`raster_lambda`; the CPU twin's is in src/cpu/raster/shade.rs). Needs `draw`
// (raster_interface.glsl) compiled with PATTERN.
#ifndef PATTERN_GLSL
#define PATTERN_GLSL
#ifdef TEXTURE
#include "texture.glsl"

// The level of detail from the quad's fine derivatives of the transformed
// coordinates: log2 of the longer of the two screen axes' steps in texels
// of level 0 (the Vulkan specification's scale factor rho). The draw's
// pattern is the same for every pixel: this is uniform control flow.
float raster_lambda(uint index, vec2 uv) {
    uvec4 level = texture_records[texture_records[index].x];
    vec2 size = vec2(level.yz);
    vec2 dx = dFdxFine(uv) * size;
    vec2 dy = dFdyFine(uv) * size;
    return log2(max(length(dx), length(dy)));
}
#endif

vec3 pattern_color(vec2 uv) {
    float scale = draw.checker_a.w;
    if (scale == 0.0) {
        return vec3(1.0);
    }
#ifdef TEXTURE
    if (scale < 0.0) {
        uint index = uint(-scale) - 1u;
        vec3 at = vec3(uv, 1.0);
        vec2 st = vec2(dot(draw.checker_a.xyz, at), dot(draw.checker_b.xyz, at));
        return sample_texture(index, st, raster_lambda(index, st));
    }
#endif
    vec2 cell = floor(scale * uv);
    return mod(cell.x + cell.y, 2.0) == 0.0 ? draw.checker_a.rgb : draw.checker_b.rgb;
}

#endif
