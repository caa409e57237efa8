// The lighting model of docs/lighting-model.md, the only copy on the GPU.
// Its CPU twin is src/cpu/lighting.rs; a change here is a change there.
//
// Needs, from the including interface: the specialization constants
// LIGHT_COUNT, USE_SPECULAR, USE_ATTENUATION and INVERSE_SQUARE, and the
// `lights` buffer.
//
// Defined answers where naive float code is undefined (the same on the CPU):
// - a zero normal (N = 0) receives the ambient term only;
// - a light exactly at the shaded point (d = 0) contributes nothing;
// - glossiness p = 0 gives S = 1 whenever N.L > 0 (x^0 = 1, even for x = 0);
// - a light must face the surface by more than rounding: N.L <= FACING_EPS
//   counts as behind the terminator. A light in the surface's own plane
//   (N.L = 0 exactly, a rounding error either side in f32) would otherwise
//   switch the whole specular term on at random (assets/hard/grazing-light.toml).
//   Near such a light the rounding of P (relative to its distance r from
//   the eye) turns L by up to about 1e-7 r / d, so the bound grows to
//   FACING_EPS r / d where the light is nearer than the eye
//   (assets/hard/light-on-surface.toml, 8 samples a pixel).
#ifndef LIGHTING_GLSL
#define LIGHTING_GLSL

// 1e-5: ten times f32 rounding of a dot product of unit vectors, and only
// 0.0006 degrees from the tangent plane.
const float FACING_EPS = 1.0e-5;

struct Surface {
    vec3 color;
    float ka;
    float kd;
    float ks;
    float p;
};

vec3 ambient_term(Surface m, vec3 ambient) {
    return ambient * m.ka * m.color;
}

// Where light j is seen from P: its direction L and distance d. False when
// it adds nothing (at P, or behind the terminator), so no shadow ray is due.
bool light_faces(int j, vec3 P, vec3 N, out vec3 L, out float d, out float n_dot_l) {
    vec3 to_light = lights[j].position.xyz - P;
    d = length(to_light);
    if (d == 0.0) {
        return false;
    }
    L = to_light / d;
    n_dot_l = dot(N, L);
    // P is camera-relative: length(P) is its distance from the eye.
    return n_dot_l > FACING_EPS * max(1.0, length(P) / d);
}

// Normalises an interpolated normal; one that has shrunk to zero stays zero.
vec3 unit_or_zero(vec3 n) {
    float len2 = dot(n, n);
    return len2 > 0.0 ? n * inversesqrt(len2) : vec3(0.0);
}

// The contribution of one light: the lighting hook, `shade_light`. The
// built-in one (lighting_hook.glsl) is the lecture's diffuse and specular
// terms; `--lighting FILE` compiles the user's file in its place
// (src/gpu/shared/hook.rs), which may use everything declared above this line.
#include "lighting_hook.glsl"

// How the raster modes turn an interpolated normal (Gouraud's vertex
// normal, Phong's per-pixel one) into the formula's N: normalised. A hook
// may define SHADELAB_SURFACE_NORMAL and its own `surface_normal` (to show
// the classic bug of an unnormalised normal, say). The ray tracer keeps
// its normals unit: they also steer its reflected and refracted rays.
#ifndef SHADELAB_SURFACE_NORMAL
vec3 surface_normal(vec3 interpolated) {
    return unit_or_zero(interpolated);
}
#endif

// Light j's contribution, given `light_faces`' results.
vec3 light_term(int j, vec3 N, vec3 V, vec3 L, float d, float n_dot_l, Surface m, float k) {
    return shade_light(N, V, L, d, lights[j].intensity.rgb, m, k);
}

// The whole formula with every light visible.
// P: camera-relative point, N: unit normal or zero, V: unit vector to the eye.
vec3 shade(vec3 P, vec3 N, vec3 V, Surface m, vec3 ambient, float k) {
    vec3 intensity = ambient_term(m, ambient);
    if (N == vec3(0.0)) {
        return intensity;
    }
    for (int j = 0; j < LIGHT_COUNT; ++j) {
        vec3 L;
        float d;
        float n_dot_l;
        if (light_faces(j, P, N, L, d, n_dot_l)) {
            intensity += light_term(j, N, V, L, d, n_dot_l, m, k);
        }
    }
    return intensity;
}

#endif
