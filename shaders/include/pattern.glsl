// The draw's pattern at texture coordinates `uv` (docs/lighting-model.md,
// "Surface colour"): a checkerboard whose cell (floor(scale u),
// floor(scale v)) has the first colour where the two add up to an even
// number; 1 for a material without a pattern. Its CPU twin is
// `Pattern::at` (src/scene/model.rs). Needs `draw` (raster_interface.glsl)
// compiled with PATTERN.
vec3 pattern_color(vec2 uv) {
    float scale = draw.checker_a.w;
    if (scale == 0.0) {
        return vec3(1.0);
    }
    vec2 cell = floor(scale * uv);
    return mod(cell.x + cell.y, 2.0) == 0.0 ? draw.checker_a.rgb : draw.checker_b.rgb;
}
