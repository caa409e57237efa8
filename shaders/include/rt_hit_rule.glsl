// The ray tracer's nearest-hit rule (docs/raytracing.md): the nearest
// t > 0 wins; a tie goes to the lower scene object, then to the lower
// triangle.
#ifndef RT_HIT_RULE_GLSL
#define RT_HIT_RULE_GLSL

#include "rt_interface.glsl"
#include "rt_ray.glsl"

// The scene object of a shape, and its place among that object's
// primitives (triangles only), for the tie rule.
uint object_of(uint shape) {
    uint index = shape & ~KIND_MASK;
    switch (shape & KIND_MASK) {
        case KIND_SPHERE:
            return sphere_word(index, SPHERE_OBJECT);
        case KIND_PLANE:
            return plane_word(index, PLANE_OBJECT);
        case KIND_BOX:
            return box_word(index, BOX_OBJECT);
        default:
            return triangle_word(index, TRI_OBJECT);
    }
}

uint order_of(uint shape) {
    return (shape & KIND_MASK) == KIND_TRIANGLE ? triangle_word(shape & ~KIND_MASK, TRI_INDEX) : 0u;
}

// Whether a hit at exactly best.t on `shape` replaces best: the lower
// object wins, then the lower triangle. Rare, so its reads cost little.
bool wins_tie(uint shape, Hit best) {
    if (best.shape == NO_SHAPE) {
        return true;
    }
    uint object = object_of(shape);
    uint best_object = object_of(best.shape);
    return object < best_object || (object == best_object && order_of(shape) < order_of(best.shape));
}

// Makes a triangle's hit at t the nearest if it is (t > 0, then the tie
// rule).
void consider_triangle(float t, uint shape, vec2 uv, inout Hit best) {
    if (t > 0.0 && t <= best.t && (t < best.t || wins_tie(shape, best))) {
        best = Hit(t, shape, uv, vec3(0.0), 0.0, 0u, 0u);
    }
}

// The same for an analytic object, whose scene object is at hand: the tie
// rule is then a comparison, not a branch to per-lane reads. Analytic
// objects are searched before the meshes, so `best` is one of them or
// none (object NO_SHAPE, above every object).
void consider_object(float t, uint shape, vec3 normal, float radius, uint material, uint object, inout Hit best) {
    if (t > 0.0 && (t < best.t || (t == best.t && object < best.object))) {
        best = Hit(t, shape, vec2(0.0), normal, radius, material, object);
    }
}

#endif
