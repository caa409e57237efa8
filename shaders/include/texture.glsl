// Image texture sampling (docs/lighting-model.md, "Image textures"): the
// f32 twin of src/cpu/sample.rs. The shader reads the texels from a storage
// buffer and filters them itself, by the reference's rules, so that no
// driver's sampler approximations (fixed-point filter weights, a level of
// detail rounded or blended otherwise) enter the image.
//
// Needs, declared before it is included: `texture_records` (uvec4: per
// texture, its first level record, level count and sampler bits; per level,
// its first texel, width and height: src/gpu/shared/texture_table.rs), `texels`
// (vec4 per texel, linear RGB), and the specialization constants
// `SAMPLER_FIXED` and `FIXED_SAMPLER`: where every image of the scene has
// one sampler, its bits, so that the branches on them fold away when the
// pipeline is built (lavapipe's code generation is then a fraction).
#ifndef TEXTURE_GLSL
#define TEXTURE_GLSL

// An index (an integer in a float, perhaps outside 0..size) wrapped into
// it: 0 repeat, 1 clamp to edge, 2 mirrored repeat. In float arithmetic:
// an integer modulo is a division per lane that the driver cannot
// vectorise (lavapipe's code generation took seconds over it). Exact while
// |i| < 2^24 / size's rounding allows: beyond some 16 million texels from
// the origin a repeat may land one texel off, and the clamp keeps it in
// the texture.
float wrap_index(float i, float size, uint mode) {
    if (mode == 1u) {
        return clamp(i, 0.0, size - 1.0);
    }
    if (mode == 2u) {
        float period = 2.0 * size;
        float m = i - period * floor(i / period);
        m = m >= size ? period - 1.0 - m : m;
        return clamp(m, 0.0, size - 1.0);
    }
    return clamp(i - size * floor(i / size), 0.0, size - 1.0);
}

// One level read with NEAREST (`linear` false) or LINEAR. Each of the
// four indices is wrapped once; NEAREST reads one texel.
vec3 filtered(uvec4 level, uint sampler_bits, bool linear, vec2 uv) {
    vec2 size = vec2(level.yz);
    vec2 xy = linear ? uv * size - 0.5 : uv * size;
    vec2 ij = floor(xy);
    vec2 f = xy - ij;
    uint wrap_u = sampler_bits & 3u;
    uint wrap_v = (sampler_bits >> 2) & 3u;
    uint x0 = uint(wrap_index(ij.x, size.x, wrap_u));
    uint y0 = uint(wrap_index(ij.y, size.y, wrap_v));
    vec3 t00 = texels[level.x + y0 * level.y + x0].rgb;
    if (!linear) {
        return t00;
    }
    uint x1 = uint(wrap_index(ij.x + 1.0, size.x, wrap_u));
    uint y1 = uint(wrap_index(ij.y + 1.0, size.y, wrap_v));
    vec3 t10 = texels[level.x + y0 * level.y + x1].rgb;
    vec3 t01 = texels[level.x + y1 * level.y + x0].rgb;
    vec3 t11 = texels[level.x + y1 * level.y + x1].rgb;
    vec3 top = t00 * (1.0 - f.x) + t10 * f.x;
    vec3 bottom = t01 * (1.0 - f.x) + t11 * f.x;
    return top * (1.0 - f.y) + bottom * f.y;
}

// Texture `index` at `uv` with level of detail `lambda`: magnification at
// lambda <= 0, else minification, within level 0 or, with mip levels, the
// nearest level (Vulkan's ceil(lambda + 0.5) - 1) or a blend of the two
// around lambda, lambda clamped to the chain. The levels are chosen first,
// so that the filter's code is there twice, not once per case.
vec3 sample_texture(uint index, vec2 uv, float lambda) {
    uvec4 texture_record = texture_records[index];
    uint bits = texture_record.z;
    if (SAMPLER_FIXED) {
        bits = FIXED_SAMPLER;
    }
    float last = float(texture_record.y - 1u);
    bool linear = (bits & 16u) != 0u;
    float level = 0.0;
    float fraction = 0.0;
    if (lambda > 0.0) {
        linear = (bits & 32u) != 0u;
        uint mip = (bits >> 6) & 3u;
        float clamped = min(lambda, last);
        if (mip == 1u) {
            level = clamp(ceil(clamped + 0.5) - 1.0, 0.0, last);
        } else if (mip == 2u) {
            level = floor(clamped);
            fraction = clamped - level;
        }
    }
    uint first = texture_record.x;
    vec3 a = filtered(texture_records[first + uint(level)], bits, linear, uv);
    if (fraction == 0.0) {
        return a;
    }
    vec3 b = filtered(texture_records[first + uint(min(level + 1.0, last))], bits, linear, uv);
    return a * (1.0 - fraction) + b * fraction;
}

// Texels per unit of uv area of texture `index` (level 0), before its
// transform.
float texel_area(uint index) {
    uvec4 level = texture_records[texture_records[index].x];
    return float(level.y) * float(level.z);
}

// The ray cones' level of detail (src/level_of_detail.rs, `cone_lambda`):
// a cone `width` wide meeting a surface of `density` texels per unit area
// at `cos`. NaN (no width and edge-on, or no texels) is 0.
float cone_lambda(float density, float width, float cos_angle) {
    float lambda = 0.5 * log2(density) + log2(width) - log2(abs(cos_angle));
    return isnan(lambda) ? 0.0 : lambda;
}

#endif
