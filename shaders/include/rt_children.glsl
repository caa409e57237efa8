// What a hit's ray branches into, shared by both directions of tracing:
// the eye's rays (rt_ray_tree.glsl) and the photons (rt_photon.glsl). The
// twin of `children` in src/cpu/raytrace/secondary_rays.rs.
#ifndef RT_CHILDREN_GLSL
#define RT_CHILDREN_GLSL

#include "rt_interface.glsl"
#include "rt_ray.glsl"
#include "rt_shading.glsl"

// What a hit's ray branches into: a reflected ray, a refracted one (its
// direction), both or neither, with their weights. A child lighter than
// the cut-off is pruned (and counted).
struct Children {
    bool reflects;
    WEIGHT reflect_weight;
    bool refracts;
    vec3 refract_dir;
    WEIGHT refract_weight;
};

Children children_of(Ray ray, vec3 N, MaterialRecord material, float cutoff) {
    float kr = material.kd_ks_p_kr.w;
    // Decided by kr and total internal reflection, not by the
    // weight, as on the CPU: a weight that underflows in f32 is
    // still a child (pruned).
    Children c = Children(kr > 0.0, ray.weight * kr, false, vec3(0.0), WEIGHT(0.0));
    if (HAS_TRANSMISSION) {
        float kt = material.kt_ior.x;
        float ior = material.kt_ior.y;
        if (kt > 0.0) {
            bool entering = dot(N, ray.dir) < 0.0;
            vec3 n = entering ? N : -N;
            float eta = entering ? 1.0 / ior : ior;
            float cos_i = -dot(n, ray.dir);
            // sin^2(i) from the part along the surface, not
            // 1 - cos^2(i): the twin in src/cpu/raytrace/secondary_rays.rs.
            vec3 along = ray.dir + cos_i * n;
            float k = 1.0 - eta * eta * dot(along, along);
            if (k < 0.0) {
                c.reflects = true;  // total internal reflection
                c.reflect_weight = ray.weight * (kr + kt);
            } else {
                c.refracts = true;
                c.refract_dir = normalize(eta * along - sqrt(k) * n);
                c.refract_weight = ray.weight * kt;
            }
        }
    }
    if (c.reflects && LARGEST(c.reflect_weight) < cutoff) {
        c.reflects = false;
        count(4);
    }
    if (c.refracts && LARGEST(c.refract_weight) < cutoff) {
        c.refracts = false;
        count(4);
    }
    return c;
}

#endif
