// The ray-query engine's nearest-hit and shadow queries (`--traversal
// query`): raytrace.comp.glsl compiled with RAY_QUERY includes this
// (through rt_search.glsl) in place of its own BVH walk; everything else
// (camera, ray tree, shading, shadows, offsets) is the same source. The
// driver walks an acceleration structure it built
// (src/gpu/raytrace/accel.rs): triangles, tested by the
// driver's own triangle test, and bounding boxes of the analytic objects,
// whose exact tests are the compute tracer's (sphere_t, plane_t, box_t).
// Triangles are opaque: the driver commits the nearest itself (by its own
// test and its own tie-break), which is what makes it fast; every analytic
// candidate goes through the compute tracer's rule against what is
// committed: the nearest t > 0 wins, ties to the lower object.
// docs/raytracing.md, "The ray-query engine", says where the two engines
// may differ.
#ifndef RT_QUERY_GLSL
#define RT_QUERY_GLSL

#include "rt_search.glsl"

layout(set = 1, binding = 0) uniform accelerationStructureEXT scene_structure;

// Instance custom indices (gpu::raytrace::accel::QUERY_*): the records an analytic
// instance's primitive indices point into. A mesh's instance has its first
// triangle record instead: a triangle hit's record is that plus the
// primitive index.
const uint QUERY_SPHERES = 0u;
const uint QUERY_PLANES = 1u;
const uint QUERY_BOXES = 2u;

// A candidate as a hit record: its distance (0 for none) and what shading
// will need. Each lane reads its own records: the query loop is not in
// uniform control flow, so no shared reads here.
Hit query_candidate(uint kind, uint index, vec3 o, vec3 d) {
    if (kind == QUERY_SPHERES) {
        SphereGeometry g = sphere_geometry(int(index));
        return Hit(sphere_t(o, d, g), KIND_SPHERE | index, vec2(0.0), g.center, g.radius, g.material, g.object);
    }
    if (kind == QUERY_PLANES) {
        PlaneGeometry g = plane_geometry(int(index));
        return Hit(plane_t(o, d, g), KIND_PLANE | index, vec2(0.0), g.normal, 0.0, g.material, g.object);
    }
    BoxGeometry g = box_geometry(int(index));
    vec2 face;
    float t = box_t(o, d, g, face);
    return Hit(t, KIND_BOX | index, vec2(0.0), box_normal(g, face), 0.0, g.material, g.object);
}

// Whether candidate `h` replaces `best`: nearer, or as near and first by
// object, then by triangle (both records carry their object).
bool query_wins(Hit h, Hit best) {
    if (h.t <= 0.0 || h.t > best.t) {
        return false;
    }
    if (h.t < best.t || best.shape == NO_SHAPE) {
        return true;
    }
    return h.object < best.object || (h.object == best.object && order_of(h.shape) < order_of(best.shape));
}

// The analytic candidate the query holds, as a hit record. Triangles are
// opaque: the driver tests them and commits the nearest itself, and only
// the analytic objects' boxes come back to the shader as candidates.
#define QUERY_CANDIDATE(q, o, d)                                                               \
    query_candidate(uint(rayQueryGetIntersectionInstanceCustomIndexEXT(q, false)),             \
                    uint(rayQueryGetIntersectionPrimitiveIndexEXT(q, false)), o, d)

// The triangle record of the hit the query has committed.
#define QUERY_RECORD(q)                                                                      \
    (uint(rayQueryGetIntersectionInstanceCustomIndexEXT(q, true))                            \
     + uint(rayQueryGetIntersectionPrimitiveIndexEXT(q, true)))

// The nearest hit so far: the triangle the driver committed, if it did,
// else `best` (an analytic hit the shader generated, or none).
#define QUERY_COMMITTED(q, best)                                                                   \
    (rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionTriangleEXT         \
         ? Hit(rayQueryGetIntersectionTEXT(q, true), KIND_TRIANGLE | QUERY_RECORD(q),               \
               rayQueryGetIntersectionBarycentricsEXT(q, true), vec3(0.0), 0.0, 0u,                 \
               triangle_word(QUERY_RECORD(q), TRI_OBJECT))                                          \
         : best)

// The nearest hit, as the compute tracer's `nearest`; `traces` false asks
// nothing.
Hit nearest(vec3 o, vec3 d, bool traces) {
    Hit best = Hit(traces ? NO_HIT : -1.0, NO_SHAPE, vec2(0.0), vec3(0.0), 0.0, 0u, NO_SHAPE);
    if (traces) {
        rayQueryEXT q;
        rayQueryInitializeEXT(q, scene_structure, gl_RayFlagsNoneEXT, 0xffu, o, 0.0, d, NO_HIT);
        while (rayQueryProceedEXT(q)) {
            Hit h = QUERY_CANDIDATE(q, o, d);
            if (query_wins(h, QUERY_COMMITTED(q, best))) {
                best = h;
                rayQueryGenerateIntersectionEXT(q, h.t);
            }
        }
        best = QUERY_COMMITTED(q, best);
    }
    if (traces) {
        consider_huge_spheres(o, d, best);
    }
    if ((best.shape & KIND_MASK) == KIND_SPHERE) {
        best.normal = (o + best.t * d - best.normal) / best.radius;
    }
    return best;
}

// Whether anything is hit at 0 < t < t_max, as the compute tracer's
// `occluded`; a negative t_max asks nothing. The first blocker ends it.
bool occluded(vec3 o, vec3 d, float t_max) {
    bool blocked = false;
    if (t_max > 0.0) {
        rayQueryEXT q;
        rayQueryInitializeEXT(q, scene_structure, gl_RayFlagsTerminateOnFirstHitEXT, 0xffu, o, 0.0, d, t_max);
        while (rayQueryProceedEXT(q)) {
            Hit h = QUERY_CANDIDATE(q, o, d);
            if (h.t > 0.0 && h.t < t_max) {
                blocked = true;
                rayQueryGenerateIntersectionEXT(q, h.t);
            }
        }
        blocked = blocked || rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionTriangleEXT;
        blocked = blocked || huge_sphere_blocks(o, d, t_max);
    }
    return blocked;
}

#endif
