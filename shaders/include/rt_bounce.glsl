// Diffuse bounces: the numbers a bounce draws and the cosine-weighted
// direction, the twins of src/cpu/raytrace/bounce.rs (docs/lighting-model.md,
// "Backward: the eye's ray tree with diffuse bounces"). The photons' flights
// (rt_photon.glsl) take their diffuse bounces' directions here too.
#ifndef RT_BOUNCE_GLSL
#define RT_BOUNCE_GLSL

#include "random_streams.glsl"

// A bounce past this many bounces is decided by Russian roulette.
const int ROULETTE_AFTER = 3;

// The two numbers of a bounce's direction and the one of its roulette, for
// the hit at tree level `level` of the sample `source` traces.
vec3 bounce_numbers(Sampler source, int level) {
    return sampler_at_level(source, level).xyz;
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

#endif
