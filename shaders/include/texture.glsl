// Image texture sampling (docs/lighting-model.md, "Image textures"): the
// f32 twin of src/cpu/sample.rs. The shader reads the texels from a storage
// buffer and filters them itself, by the reference's rules, so that no
// driver's sampler approximations (fixed-point filter weights, a level of
// detail rounded or blended otherwise) enter the image.
//
// Needs, declared before it is included: `texture_records` (uvec4: per
// texture, its first level record, level count and sampler bits; per level,
// its first texel, width and height: src/gpu/texture_table.rs) and
// `texels` (three floats per texel, linear RGB).

// `k` modulo `n` in 0..n, also for a negative `k` (GLSL's % is undefined
// for negative operands).
int euclid_mod(int k, int n) {
    return k >= 0 ? k % n : (n - 1) - ((-k - 1) % n);
}

// An index (an integer, perhaps outside 0..size) wrapped into it: 0 repeat,
// 1 clamp to edge, 2 mirrored repeat.
int wrap_index(float i, int size, uint mode) {
    // Far outside the texture the coordinate has no precision left to
    // place a texel; bounded so that the conversion stays defined.
    int k = int(clamp(i, -1.0e9, 1.0e9));
    if (mode == 1u) {
        return clamp(k, 0, size - 1);
    }
    if (mode == 2u) {
        int m = euclid_mod(k, 2 * size);
        return m >= size ? 2 * size - 1 - m : m;
    }
    return euclid_mod(k, size);
}

vec3 texel_at(uvec4 level, uint sampler_bits, float i, float j) {
    int w = int(level.y);
    int h = int(level.z);
    int x = wrap_index(i, w, sampler_bits & 3u);
    int y = wrap_index(j, h, (sampler_bits >> 2) & 3u);
    uint k = 3u * (level.x + uint(y * w + x));
    return vec3(texels[k], texels[k + 1u], texels[k + 2u]);
}

// One level read with NEAREST (`linear` false) or LINEAR.
vec3 filtered(uvec4 level, uint sampler_bits, bool linear, vec2 uv) {
    vec2 size = vec2(level.yz);
    if (!linear) {
        return texel_at(level, sampler_bits, floor(uv.x * size.x), floor(uv.y * size.y));
    }
    vec2 xy = uv * size - 0.5;
    vec2 ij = floor(xy);
    vec2 f = xy - ij;
    vec3 top = texel_at(level, sampler_bits, ij.x, ij.y) * (1.0 - f.x)
               + texel_at(level, sampler_bits, ij.x + 1.0, ij.y) * f.x;
    vec3 bottom = texel_at(level, sampler_bits, ij.x, ij.y + 1.0) * (1.0 - f.x)
                  + texel_at(level, sampler_bits, ij.x + 1.0, ij.y + 1.0) * f.x;
    return top * (1.0 - f.y) + bottom * f.y;
}

// Texture `index` at `uv` with level of detail `lambda`: magnification at
// lambda <= 0, else minification, within level 0 or, with mip levels, the
// nearest level (Vulkan's ceil(lambda + 0.5) - 1) or a blend of the two
// around lambda, lambda clamped to the chain.
vec3 sample_texture(uint index, vec2 uv, float lambda) {
    uvec4 texture_record = texture_records[index];
    uint bits = texture_record.z;
    uint first = texture_record.x;
    if (lambda <= 0.0) {
        return filtered(texture_records[first], bits, (bits & 16u) != 0u, uv);
    }
    bool linear = (bits & 32u) != 0u;
    uint mip = (bits >> 6) & 3u;
    float last = float(texture_record.y - 1u);
    lambda = min(lambda, last);
    if (mip == 0u) {
        return filtered(texture_records[first], bits, linear, uv);
    }
    if (mip == 1u) {
        float level = clamp(ceil(lambda + 0.5) - 1.0, 0.0, last);
        return filtered(texture_records[first + uint(level)], bits, linear, uv);
    }
    float lower = floor(lambda);
    float fraction = lambda - lower;
    vec3 a = filtered(texture_records[first + uint(lower)], bits, linear, uv);
    if (fraction == 0.0) {
        return a;
    }
    vec3 b = filtered(texture_records[first + uint(min(lower + 1.0, last))], bits, linear, uv);
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
