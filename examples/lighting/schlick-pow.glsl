// Schlick's rational approximation of the specular power (Schlick 1994,
// "A fast alternative to Phong's specular model"): x^p ~ x / (p - p x + x).
// Trades: a division for pow (exp2 and log2 on most hardware), with a
// highlight of about the same width but a longer, brighter tail.
vec3 shade_light(vec3 N, vec3 V, vec3 L, float d, vec3 intensity, Surface m, float k) {
    vec3 light = USE_ATTENUATION ? intensity / (INVERSE_SQUARE ? d * d : d + k) : intensity;
    float n_dot_l = dot(N, L);
    vec3 reflected = m.kd * m.color * n_dot_l;
    if (USE_SPECULAR) {
        vec3 R = 2.0 * n_dot_l * N - L;
        float x = max(dot(R, V), 0.0);
        float s = m.p == 0.0 ? 1.0 : x / (m.p - m.p * x + x);
        reflected += vec3(m.ks * s);
    }
    return light * reflected;
}
