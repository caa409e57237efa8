// The lighting model of docs/lighting-model.md, the only copy on the GPU.
// Its CPU twin is src/cpu/lighting.rs; a change here is a change there.
//
// Defined answers where naive float code is undefined (the same on the CPU):
// - a zero normal (N = 0) receives the ambient term only;
// - a light exactly at the shaded point (d = 0) contributes nothing;
// - glossiness p = 0 gives S = 1 whenever N.L > 0 (x^0 = 1, even for x = 0).

struct Surface {
    vec3 color;
    float ka;
    float kd;
    float ks;
    float p;
};

Surface draw_surface() {
    return Surface(draw.color_ka.rgb, draw.color_ka.a, draw.kd_ks_p.x, draw.kd_ks_p.y, draw.kd_ks_p.z);
}

// P: camera-relative point, N: unit normal or zero, V: unit vector to the eye.
vec3 shade(vec3 P, vec3 N, vec3 V, Surface m) {
    vec3 intensity = frame.ambient_k.rgb * m.ka * m.color;
    if (N == vec3(0.0)) {
        return intensity;
    }
    for (int j = 0; j < LIGHT_COUNT; ++j) {
        vec3 to_light = lights[j].position.xyz - P;
        float d = length(to_light);
        if (d == 0.0) {
            continue;
        }
        vec3 L = to_light / d;
        float n_dot_l = dot(N, L);
        if (n_dot_l <= 0.0) {
            continue;  // both terms vanish behind the terminator
        }
        vec3 light = lights[j].intensity.rgb;
        if (USE_ATTENUATION) {
            light /= d + frame.ambient_k.w;
        }
        vec3 reflected = m.kd * m.color * n_dot_l;
        if (USE_SPECULAR) {
            vec3 R = 2.0 * n_dot_l * N - L;
            float r_dot_v = max(dot(R, V), 0.0);
            float s = m.p == 0.0 ? 1.0 : (r_dot_v > 0.0 ? pow(r_dot_v, m.p) : 0.0);
            reflected += vec3(m.ks * s);
        }
        intensity += light * reflected;
    }
    return intensity;
}

// Normalises an interpolated normal; one that has shrunk to zero stays zero.
vec3 unit_or_zero(vec3 n) {
    float len2 = dot(n, n);
    return len2 > 0.0 ? n * inversesqrt(len2) : vec3(0.0);
}
