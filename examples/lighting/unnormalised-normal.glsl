// The classic bug: the interpolated normal used as it comes. Between the
// vertices of a curved mesh the interpolated normal is shorter than 1, so
// N.L and R.V shrink and every triangle's interior darkens, most on a
// coarse mesh; at the vertices it is exact. Only Phong shows it: Gouraud
// evaluates the formula at the vertices, whose normals are unit. Trades:
// one inversesqrt per pixel saved, for visible facets on a smooth sphere.
#define SHADELAB_SURFACE_NORMAL
vec3 surface_normal(vec3 interpolated) {
    return interpolated;
}

// The lecture's formula, unchanged (phong.glsl).
vec3 shade_light(vec3 N, vec3 V, vec3 L, float d, vec3 intensity, Surface m, float k) {
    vec3 light = USE_ATTENUATION ? intensity / (INVERSE_SQUARE ? d * d : d + k) : intensity;
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
