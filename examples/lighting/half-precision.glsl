// Half precision: the whole per-light formula in 16-bit floats, where the
// device has shaderFloat16 (lavapipe does; shadelab enables it where the
// device offers it and refuses this hook with exit status 2 where not).
// Trades: half the register and bandwidth cost on GPUs with fast fp16
// (none on lavapipe, which computes them in 32-bit lanes) for 11 bits of
// mantissa: intensities near 1 carry errors of about 1e-3, and pow of a
// value near 1 loses the most (a highlight's tail).
#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require

vec3 shade_light(vec3 N, vec3 V, vec3 L, float d, vec3 intensity, Surface m, float k) {
    f16vec3 n = f16vec3(N);
    f16vec3 l = f16vec3(L);
    f16vec3 light = f16vec3(USE_ATTENUATION ? intensity / (INVERSE_SQUARE ? d * d : d + k) : intensity);
    float16_t n_dot_l = dot(n, l);
    f16vec3 reflected = float16_t(m.kd) * f16vec3(m.color) * n_dot_l;
    if (USE_SPECULAR) {
        f16vec3 r = float16_t(2.0) * n_dot_l * n - l;
        float16_t r_dot_v = max(dot(r, f16vec3(V)), float16_t(0.0));
        float16_t s = m.p == 0.0 ? float16_t(1.0)
                    : (r_dot_v > float16_t(0.0) ? pow(r_dot_v, float16_t(m.p)) : float16_t(0.0));
        reflected += f16vec3(float16_t(m.ks) * s);
    }
    return vec3(light * reflected);
}
