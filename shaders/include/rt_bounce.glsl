// Diffuse bounces (secondary illumination, compiled with PATHS): the
// counter-based random numbers and the cosine-weighted direction, the twins
// of src/cpu/raytrace/bounce.rs (docs/lighting-model.md, "Backward: the
// eye's ray tree with diffuse bounces").

// A bounce past this many bounces is decided by Russian roulette.
const int ROULETTE_AFTER = 3;

// Jarzynski and Olano's 4-D hash (2020): a counter in, four words out.
uvec4 pcg4d(uvec4 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    return v;
}

// The two numbers of a bounce's direction and the one of its roulette, for
// the hit at tree level `level` of sample `key.y` of pixel `key.x`: the top
// 24 bits of each word, exact in f32 (the CPU's f64 starts from the same).
vec3 bounce_numbers(uvec2 key, int level) {
    uvec4 x = pcg4d(uvec4(key, uint(level), 0u));
    return vec3(x.xyz >> 8u) * (1.0 / 16777216.0);
}

// A direction about the unit normal n distributed as (n.w) / pi, in the
// frame Duff et al. (2017) complete n to.
vec3 cosine_direction(vec3 n, float u0, float u1) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float b = n.x * n.y * a;
    vec3 t = vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    vec3 bitangent = vec3(b, s + n.y * n.y * a, -n.y);
    float phi = 6.283185307179586 * u0;
    float r = sqrt(u1);
    return r * cos(phi) * t + r * sin(phi) * bitangent + sqrt(max(1.0 - u1, 0.0)) * n;
}
