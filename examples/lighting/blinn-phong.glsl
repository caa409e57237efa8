// Blinn-Phong: the specular term from the half vector H = (L + V) / |L + V|
// instead of the mirror direction R. Trades: one normalize instead of the
// reflection, and a highlight that is wider for the same p (N.H is closer
// to 1 than R.V; about 4p matches Phong's size at normal incidence, which
// this hook leaves out on purpose, so the difference shows).
vec3 shade_light(vec3 N, vec3 V, vec3 L, float d, vec3 intensity, Surface m, float k) {
    vec3 light = USE_ATTENUATION ? intensity / (INVERSE_SQUARE ? d * d : d + k) : intensity;
    vec3 reflected = m.kd * m.color * dot(N, L);
    if (USE_SPECULAR) {
        vec3 H = normalize(L + V);
        float n_dot_h = max(dot(N, H), 0.0);
        float s = m.p == 0.0 ? 1.0 : (n_dot_h > 0.0 ? pow(n_dot_h, m.p) : 0.0);
        reflected += vec3(m.ks * s);
    }
    return light * reflected;
}
