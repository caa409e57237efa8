// The ray tracer's local shading: secondary rays' origins off the surface,
// the materials, and every light's term with its shadow ray.
#ifndef RT_SHADING_GLSL
#define RT_SHADING_GLSL

#include "kernel_sizes.glsl"
#include "rt_interface.glsl"
#include "lighting.glsl"
#include "rt_ray.glsl"
#include "rt_search.glsl"
#include "rt_surface.glsl"

// 1e-4 of the larger of the hit's and its ray's origin's largest
// coordinate: what the hit's rounding grows with (`offset_epsilon` in
// src/cpu/raytrace/secondary_rays.rs).
float offset_epsilon(vec3 p, vec3 o) {
    vec3 a = max(abs(p), abs(o));
    return 1.0e-4 * max(a.x, max(a.y, a.z));
}

// Pushes a secondary ray's origin off the surface, to the side it leaves to.
vec3 offset_origin(vec3 p, vec3 o, vec3 geometric, vec3 dir) {
    float eps = offset_epsilon(p, o);
    float side = dot(geometric, dir) >= 0.0 ? 1.0 : -1.0;
    return p + side * eps * geometric;
}

// What a hit's material holds. Fields are read one by one: naga's SPIR-V
// reader lacks OpCopyLogical, which a whole-struct copy out of a buffer
// would emit.
struct MaterialRecord {
    vec4 color_ka;
    vec4 kd_ks_p_kr;
    vec2 kt_ior;
};

MaterialRecord material_record(uint index) {
    return MaterialRecord(materials[index].color_ka, materials[index].kd_ks_p_kr, materials[index].kt_ior.xy);
}

// A scene's few materials, read once per invocation (`main`) when
// MATERIALS_LISTED, like the listed objects. A material read at an index
// that differs between lanes is a scalar load per lane and word, each with
// a bounds check (80 for a subgroup of 8); picking it from these by
// selects is a comparison and 10 blends per material. The four spheres
// took 0.83x to 0.86x the time. (Picking by selects from materials read at
// constant indices where picked, before they were read once, was no
// faster.) Sized in raytrace.comp.glsl.
MaterialRecord listed_materials[UNROLLED_MATERIALS];

void read_listed_materials() {
    for (int i = 0; i < MATERIAL_COUNT; ++i) {
        listed_materials[i] = material_record(uint(i));
    }
}

MaterialRecord material_at(uint index) {
    if (MATERIALS_LISTED) {
        MaterialRecord m = listed_materials[0];
        for (int i = 1; i < MATERIAL_COUNT; ++i) {
            if (index == uint(i)) {
                m = listed_materials[i];
            }
        }
        return m;
    }
    return material_record(index);
}

Surface surface_of(MaterialRecord m) {
    return Surface(m.color_ka.rgb, m.color_ka.a, m.kd_ks_p_kr.x, m.kd_ks_p_kr.y, m.kd_ks_p_kr.z);
}

// The local model at a hit, shadow rays included. Call in uniform control
// flow (shadow rays walk the BVH as packets); a lane whose `lit` is false
// casts none and gets the ambient term.
vec3 local_shading(Surfel s, Surface m, vec3 origin, vec3 d, bool lit) {
    vec3 intensity = ambient_term(m, frame.ambient_k.rgb);
    // The side the ray arrives on is lit (`facing_normal` in
    // src/cpu/raytrace/secondary_rays.rs): seen from behind its geometric normal, the
    // surface's back, with the shading normal negated.
    vec3 N = dot(s.geometric, d) > 0.0 ? -s.normal : s.normal;
    lit = lit && N != vec3(0.0);
    for (int j = 0; j < LIGHT_COUNT; ++j) {
        vec3 L = vec3(0.0, 0.0, 1.0);
        float dist = 0.0;
        float n_dot_l = 0.0;
        bool faces = lit && light_faces(j, s.p, N, L, dist, n_dot_l);
        if (SHADOWS) {
            vec3 o = offset_origin(s.p, origin, s.geometric, L);
            vec3 to_light = lights[j].position.xyz - o;
            float reach = length(to_light);
            // Stop short of the light by the offset epsilon at the light, as
            // the ray starts off the surface: a light lying on a surface would
            // otherwise be hidden by it at random (assets/hard/grazing-light.toml).
            float light_eps = offset_epsilon(lights[j].position.xyz, o);
            bool casts = faces && reach > 0.0;
            vec3 dir = casts ? to_light / reach : vec3(0.0, 0.0, 1.0);
            if (faces) {
                count(1);
            }
            if (occluded(o, dir, casts ? reach - light_eps : -1.0)) {
                faces = false;
            }
        }
        if (faces) {
            intensity += light_term(j, N, -d, L, dist, n_dot_l, m, frame.ambient_k.w);
        }
    }
    return intensity;
}

#endif
