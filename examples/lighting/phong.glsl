// The lecture's formula, written as a user hook: the built-in hook
// (shaders/include/lighting_hook.glsl) line for line. It trades nothing; it
// is the baseline the other hooks are measured against, and the test that a
// hook is compiled into every mode renders it (tests/gpu/lighting_hook.rs).
vec3 shade_light(vec3 N, vec3 V, vec3 L, float d, vec3 intensity, Surface m, float k) {
    vec3 light = intensity;
    if (USE_ATTENUATION) {
        light /= INVERSE_SQUARE ? d * d : d + k;
    }
    float n_dot_l = dot(N, L);
    vec3 reflected = m.kd * m.color * n_dot_l;
    if (USE_SPECULAR) {
        vec3 R = 2.0 * n_dot_l * N - L;
        float r_dot_v = max(dot(R, V), 0.0);
        float s = m.p == 0.0 ? 1.0 : (r_dot_v > 0.0 ? pow(r_dot_v, m.p) : 0.0);
        reflected += vec3(m.ks * s);
    }
    return light * reflected;
}
