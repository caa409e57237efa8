// The built-in lighting hook: one light's diffuse and specular terms, as
// docs/lighting-model.md defines them (its CPU twin: src/cpu/lighting.rs).
// A user's hook replaces this file (`--lighting FILE`) and is held to the
// same interface (docs/lighting-hooks.md):
//   N, V, L: unit normal, unit vector to the viewer, unit vector to the light
//            (N.L > FACING_EPS max(1, r / d): the light faces the surface;
//            shadows decided)
//   d:       the distance to the light
//   intensity: the light's Il (RGB)
//   m:       the material (color, ka, kd, ks, p)
//   k:       the attenuation constant of Il / (d + k)
// and may read the specialization constants USE_SPECULAR, USE_ATTENUATION
// and INVERSE_SQUARE (the scene's falloff: with USE_ATTENUATION, Il / d^2
// when set, else Il / (d + k); without it, Il).
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
