// The ray tracer's (raytrace.comp.glsl) rays and hit records, and the
// counts of the rays it traced that it reports with COUNT_RAYS.
#ifndef RT_RAY_GLSL
#define RT_RAY_GLSL

#include "rt_interface.glsl"

// Beyond every hit: the distance limit of a ray that has found none yet.
const float NO_HIT = 3.0e38;

// What a hit was on: the kind in the top two bits, the index in that
// kind's buffer below (triangles: BVH leaf order).
const uint KIND_SPHERE = 0u << 30;
const uint KIND_PLANE = 1u << 30;
const uint KIND_BOX = 2u << 30;
const uint KIND_TRIANGLE = 3u << 30;
const uint KIND_MASK = 3u << 30;
const uint NO_SHAPE = 0xffffffffu;

// The nearest hit so far. A triangle's normals and material are read once
// the search is over (`resolve`).
struct Hit {
    float t;
    uint shape;  // KIND_* | index, or NO_SHAPE
    vec2 uv;     // triangle: barycentrics of p1 and p2
    // An analytic object's normal and material, known (at constant-index
    // reads) when it is hit; a triangle's are read after the search. A
    // sphere's normal is computed once the search is over: until then
    // `normal` holds its centre and `radius` its radius (0 for others).
    vec3 normal;
    float radius;
    uint material;
    // An analytic object's scene object, for the tie rule (a triangle's is
    // read only when a tie needs it, in wins_tie).
    uint object;
};

#ifdef PATHS
// Diffuse bounces (docs/lighting-model.md, "Secondary illumination")
// multiply a ray's weight by a colour: weights are RGB, and a ray knows the
// bounces its path has taken.
#define WEIGHT vec3
#define LARGEST(w) max((w).x, max((w).y, (w).z))
struct Ray {
    vec3 origin;
    vec3 dir;
    vec3 weight;
    int depth;
    int bounces;
};
#else
#define WEIGHT float
#define LARGEST(w) (w)
struct Ray {
    vec3 origin;
    vec3 dir;
    float weight;
    int depth;
};
#endif

uint local_counts[5];  // primary, shadow, reflected, refracted, pruned
int deepest = 0;

void count(int kind) {
    if (COUNT_RAYS) {
        local_counts[kind] += 1u;
    }
}

#endif
