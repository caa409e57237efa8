#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_shuffle : require
#ifdef RAY_QUERY
#extension GL_EXT_ray_query : require
#endif
// Backward (Whitted) ray tracing, exactly as docs/raytracing.md specifies
// (its CPU twin is src/cpu/raytrace/): stratified samples, nearest hits
// with the object-order tie rule, shadow rays, reflection and refraction
// with total internal reflection.
//
// Shaped for lavapipe, which runs a subgroup's 8 invocations in the lanes
// of one SIMD register: a branch costs what the union of its lanes' paths
// costs, and a buffer read at an index that differs between lanes costs a
// scalar load per lane and 4-byte component (docs/raytracing.md, "Why the
// shader is shaped this way"). So a subgroup's rays walk the BVH together,
// as one packet: each lane reads one 8-byte piece of a node or triangle and
// shuffles hand the pieces to every lane. Whatever only the nearest hit
// needs (normals, material) is read once, per lane, after the search.
//
// Packets need every lane of the subgroup present wherever a shuffle runs:
// the walk, and every call that leads to one, is in uniform control flow.
// A lane with nothing to trace (a pixel off the image, a ray tree that has
// ended, a light behind the surface) takes part with a negative distance
// limit, which no box or primitive passes.

// 64 invocations; how many workgroups run does not matter (see main).
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

#include "rt_interface.glsl"
#include "lighting.glsl"
#include "texture.glsl"

// Depth is at most 64 (checked on the host). Only a ray that both reflects
// and refracts leaves a ray waiting, one per level.
const int STACK_SIZE = 64;
// Packets each subgroup traces per work item (rt_layout::ITEM_PACKETS): a
// 4 x 4 arrangement of packets, each packet 4 pixels wide, so an item is
// ITEM_WIDTH pixels wide.
const uint ITEM_PACKETS = 16u;
const uint ITEM_WIDTH = 16u;
const int BVH_STACK_SIZE = 64;
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

struct Ray {
    vec3 origin;
    vec3 dir;
    float weight;
    int depth;
};

uint local_counts[5];  // primary, shadow, reflected, refracted, pruned
int deepest = 0;

void count(int kind) {
    if (COUNT_RAYS) {
        local_counts[kind] += 1u;
    }
}

// The OR of `v` over the subgroup; every lane must be here. A butterfly of
// shuffles, written out: lavapipe does not unroll a loop over the steps,
// and a loop costs it far more than the shuffles; subgroupAny and
// subgroupOr are scalar loops over the lanes there. Sizes up to 64 (the
// tests on gl_SubgroupSize fold away where the driver knows it).
uint or_lanes(uint v) {
    uint lane = gl_SubgroupInvocationID;
    v |= subgroupShuffle(v, lane ^ 1u);
    if (gl_SubgroupSize > 2u) {
        v |= subgroupShuffle(v, lane ^ 2u);
    }
    if (gl_SubgroupSize > 4u) {
        v |= subgroupShuffle(v, lane ^ 4u);
    }
    if (gl_SubgroupSize > 8u) {
        v |= subgroupShuffle(v, lane ^ 8u);
    }
    if (gl_SubgroupSize > 16u) {
        v |= subgroupShuffle(v, lane ^ 16u);
    }
    if (gl_SubgroupSize > 32u) {
        v |= subgroupShuffle(v, lane ^ 32u);
    }
    return v;
}

bool packet_any(bool b) {
    return or_lanes(b ? 1u : 0u) != 0u;
}

// A record read by the whole subgroup, as quads of words: lane i holds the
// record's quads i and i + S (S = gl_SubgroupSize; the host requires
// 4 <= S <= 64, and no record has more than 8 quads). Every lane must be
// here; the record's index must be the same in all of them. On lavapipe a
// lane's load is a loop over the lanes, each lane's part with its own
// address and a bounds check per word: the loads of four words a lane took
// fewer of those loops than pairs did (the 40k sphere 13.5 % fewer
// instructions; docs/performance.md).
struct Shared {
    uvec4 q0;
    uvec4 q1;
};

// Word `w` of a shared record, in every lane (with `w` a constant and the
// subgroup size known to the driver, one shuffle).
uint word(Shared r, uint w) {
    uint quad = w >> 2;
    uvec4 held = quad / gl_SubgroupSize == 0u ? r.q0 : r.q1;
    return subgroupShuffle(held[w & 3u], quad % gl_SubgroupSize);
}

vec3 vec3_at(Shared r, uint w) {
    return uintBitsToFloat(uvec3(word(r, w), word(r, w + 1u), word(r, w + 2u)));
}

float float_at(Shared r, uint w) {
    return uintBitsToFloat(word(r, w));
}

// read_X(index): record `index` of buffer X, shared (see Shared).
#define SHARED_READER(name, buffer, quads)                                \
    Shared name(uint index) {                                             \
        uint lane = gl_SubgroupInvocationID;                              \
        uint at = index * (quads) + lane;                                 \
        Shared r = Shared(uvec4(0u), uvec4(0u));                          \
        if (lane < (quads)) {                                             \
            r.q0 = buffer[at];                                            \
        }                                                                 \
        if (lane + gl_SubgroupSize < (quads)) {                           \
            r.q1 = buffer[at + gl_SubgroupSize];                          \
        }                                                                 \
        return r;                                                         \
    }

// X_word(index, w): word `w` of record `index`, read by this lane alone.
#define LANE_READER(name, buffer, quads)                                  \
    uint name(uint index, uint w) {                                       \
        return buffer[index * (quads) + (w >> 2)][w & 3u];                \
    }

#ifdef WIDE_BVH
SHARED_READER(read_wide_node, node_quads, WIDE_NODE_QUADS)
#else
SHARED_READER(read_node, node_quads, NODE_QUADS)
#endif
SHARED_READER(read_triangle, triangle_quads, TRI_QUADS)
SHARED_READER(read_sphere, sphere_quads, SPHERE_QUADS)
SHARED_READER(read_plane, plane_quads, PLANE_QUADS)
SHARED_READER(read_box, box_quads, BOX_QUADS)
LANE_READER(triangle_word, triangle_quads, TRI_QUADS)
LANE_READER(sphere_word, sphere_quads, SPHERE_QUADS)
LANE_READER(plane_word, plane_quads, PLANE_QUADS)
LANE_READER(box_word, box_quads, BOX_QUADS)

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

// The analytic objects' geometry. In the loops over the objects tested one
// by one (which unroll) `X_geometry(i)` reads each record at a constant
// index, one load for the subgroup. In the BVH's leaves the index is a
// variable, which would make every lane read every word on its own: there
// the subgroup shares the reads (`shared_X`).
struct SphereGeometry {
    vec3 center;
    float radius;
    uint material;
    uint object;
};

SphereGeometry shared_sphere(uint i) {
    Shared r = read_sphere(i);
    return SphereGeometry(vec3_at(r, SPHERE_CENTER), float_at(r, SPHERE_RADIUS), word(r, SPHERE_MATERIAL),
                          word(r, SPHERE_OBJECT));
}

SphereGeometry sphere_geometry(int i) {
    // Whole quads at the offsets SPHERE_CENTER (0), SPHERE_RADIUS (3),
    // SPHERE_MATERIAL (4) and SPHERE_OBJECT (5), each read once (reading
    // word by word, which read some words twice, measured slower on the
    // four spheres).
    uint at = uint(i) * SPHERE_QUADS;
    uvec4 center_radius = sphere_quads[at];
    uvec4 material_object = sphere_quads[at + 1u];
    return SphereGeometry(uintBitsToFloat(center_radius.xyz), uintBitsToFloat(center_radius.w), material_object.x,
                          material_object.y);
}

struct PlaneGeometry {
    vec3 center;
    float half_size;
    vec3 normal;
    vec3 u;
    vec3 v;
    uint material;
    uint object;
};

PlaneGeometry shared_plane(uint i) {
    Shared r = read_plane(i);
    return PlaneGeometry(vec3_at(r, PLANE_CENTER), float_at(r, PLANE_HALF), vec3_at(r, PLANE_NORMAL),
                         vec3_at(r, PLANE_U), vec3_at(r, PLANE_V), word(r, PLANE_MATERIAL), word(r, PLANE_OBJECT));
}

PlaneGeometry plane_geometry(int i) {
    // Whole quads, as for spheres: PLANE_CENTER 0, PLANE_HALF 3,
    // PLANE_NORMAL 4, PLANE_U 8, PLANE_V 12, PLANE_MATERIAL 16, PLANE_OBJECT 17.
    uint at = uint(i) * PLANE_QUADS;
    uvec4 center_half = plane_quads[at];
    uvec4 material_object = plane_quads[at + 4u];
    return PlaneGeometry(uintBitsToFloat(center_half.xyz), uintBitsToFloat(center_half.w),
                         uintBitsToFloat(plane_quads[at + 1u].xyz), uintBitsToFloat(plane_quads[at + 2u].xyz),
                         uintBitsToFloat(plane_quads[at + 3u].xyz), material_object.x, material_object.y);
}

struct BoxGeometry {
    vec3 center;
    vec3 half_extents;
    mat3 rotation;  // box-local axes to world axes
    uint material;
    uint object;
};

BoxGeometry shared_box(uint i) {
    Shared r = read_box(i);
    return BoxGeometry(vec3_at(r, BOX_CENTER), vec3_at(r, BOX_HALF),
                       mat3(vec3_at(r, BOX_AXIS_X), vec3_at(r, BOX_AXIS_Y), vec3_at(r, BOX_AXIS_Z)),
                       word(r, BOX_MATERIAL), word(r, BOX_OBJECT));
}

BoxGeometry box_geometry(int i) {
    // Whole quads, as for spheres: BOX_CENTER 0, BOX_HALF 4, BOX_AXIS_X 8,
    // BOX_AXIS_Y 12, BOX_AXIS_Z 16, BOX_MATERIAL 20, BOX_OBJECT 21.
    uint at = uint(i) * BOX_QUADS;
    vec3 v[5];
    for (uint k = 0u; k < 5u; ++k) {
        v[k] = uintBitsToFloat(box_quads[at + k].xyz);
    }
    uvec4 material_object = box_quads[at + 5u];
    return BoxGeometry(v[0], v[1], mat3(v[2], v[3], v[4]), material_object.x, material_object.y);
}

// The objects tested one by one, read once per invocation (`main`) into
// private arrays that only constant indices reach once the loops over
// them unroll, so the driver keeps them in registers and spill slots. Read
// where they are tested, each word was a load of its own with a bounds
// check, reloaded for every test: the four spheres took 0.75x the time
// with them read once. Sized as rt_layout::UNROLLED_* (longer lists go
// into the BVH).
const int UNROLLED_SPHERES = 16;
const int UNROLLED_PLANES = 12;
const int UNROLLED_BOXES = 6;
SphereGeometry listed_spheres[UNROLLED_SPHERES];
PlaneGeometry listed_planes[UNROLLED_PLANES];
BoxGeometry listed_boxes[UNROLLED_BOXES];

void read_listed_objects() {
    for (int i = 0; i < SPHERE_COUNT; ++i) {
        listed_spheres[i] = sphere_geometry(i);
    }
    for (int i = 0; i < PLANE_COUNT; ++i) {
        listed_planes[i] = plane_geometry(i);
    }
    for (int i = 0; i < BOX_COUNT; ++i) {
        listed_boxes[i] = box_geometry(i);
    }
}

// Distance to a sphere along the ray, or 0 for none (the stable form).
// The square root and the division sit in one branch, which the driver
// skips when no lane's line meets the sphere, as for most spheres most
// packets test (two early returns let it flatten the square root into
// straight-line code that every test paid).
float sphere_t(vec3 o, vec3 d, SphereGeometry s) {
    vec3 c = s.center;
    float r = s.radius;
    vec3 f = o - c;
    float b = -dot(f, d);
    vec3 l = f + b * d;
    float disc = r * r - dot(l, l);
    float t = 0.0;
    if (disc >= 0.0) {
        float q = b + (b >= 0.0 ? 1.0 : -1.0) * sqrt(disc);
        float t0 = (dot(f, f) - r * r) / q;
        float t1 = q;
        float nearer = min(t0, t1) > 0.0 ? min(t0, t1) : max(t0, t1);
        t = q == 0.0 ? 0.0 : nearer;
    }
    return t;
}

// A huge sphere (src/huge_sphere.rs): its first record as any sphere's,
// then its anchor (the surface point nearest the eye), 1 / r and the
// outward normal there.
struct HugeSphere {
    SphereGeometry sphere;
    vec3 anchor;
    float inv_radius;
    vec3 normal;
};

HugeSphere huge_sphere(int j) {
    int record = int(frame.grid.z) + 2 * j;
    uvec4 anchor = sphere_quads[uint(record + 1) * SPHERE_QUADS];
    uvec4 normal = sphere_quads[uint(record + 1) * SPHERE_QUADS + 1u];
    return HugeSphere(sphere_geometry(record), uintBitsToFloat(anchor.xyz), uintBitsToFloat(anchor.w),
                      uintBitsToFloat(normal.xyz));
}

// The anchored form (docs/raytracing.md, "Huge sphere"): with
// g = o - anchor, `cr = g.(g/r + 2n)` is `c / r` with its r^2 terms
// cancelled in the algebra rather than in f32; the near root `cr / q`
// then keeps every digit, where `sphere_t`'s `f.f - r^2` keeps none.
float huge_sphere_t(vec3 o, vec3 d, HugeSphere s) {
    vec3 g = o - s.anchor;
    float cr = dot(g, g * s.inv_radius + 2.0 * s.normal);
    float b = -dot(g, d) * s.inv_radius - dot(s.normal, d);
    float disc = b * b - cr * s.inv_radius;
    float t = 0.0;
    if (disc >= 0.0) {
        float q = b + (b >= 0.0 ? 1.0 : -1.0) * sqrt(disc);
        float t0 = cr / q;
        float t1 = q * s.sphere.radius;
        float nearer = min(t0, t1) > 0.0 ? min(t0, t1) : max(t0, t1);
        t = q == 0.0 ? 0.0 : nearer;
    }
    return t;
}

float plane_t(vec3 o, vec3 d, PlaneGeometry p) {
    float denom = dot(d, p.normal);
    if (denom == 0.0) {
        return 0.0;
    }
    float t = dot(p.center - o, p.normal) / denom;
    vec3 rel = o + t * d - p.center;
    bool inside = abs(dot(rel, p.u)) <= p.half_size && abs(dot(rel, p.v)) <= p.half_size;
    return inside ? t : 0.0;
}

// Distance to a box, or 0; `face` gets the axis of the face hit and the
// sign of its outward normal (box-local).
float box_t(vec3 o, vec3 d, BoxGeometry box, out vec2 face) {
    mat3 rot = box.rotation;
    vec3 h = box.half_extents;
    vec3 lo = transpose(rot) * (o - box.center);
    vec3 ld = transpose(rot) * d;
    float t_near = -NO_HIT;
    float t_far = NO_HIT;
    int near_axis = 0;
    int far_axis = 0;
    bool outside = false;
    for (int a = 0; a < 3; ++a) {
        if (ld[a] == 0.0) {
            outside = outside || abs(lo[a]) > h[a];
            continue;
        }
        float t1 = (-h[a] - lo[a]) / ld[a];
        float t2 = (h[a] - lo[a]) / ld[a];
        float t_in = min(t1, t2);
        float t_out = max(t1, t2);
        if (t_in > t_near) {
            t_near = t_in;
            near_axis = a;
        }
        if (t_out < t_far) {
            t_far = t_out;
            far_axis = a;
        }
    }
    face = vec2(0.0);
    if (outside || t_far < max(t_near, 0.0)) {
        return 0.0;
    }
    float t = t_near > 0.0 ? t_near : t_far;
    int axis = t_near > 0.0 ? near_axis : far_axis;
    face = vec2(float(axis), (lo[axis] + t * ld[axis]) >= 0.0 ? 1.0 : -1.0);
    return t;
}

// Whether the line of the ray (o, unit d) passes within the sphere of
// centre c and squared radius r2: a test with no division that lets a
// packet skip the work on something none of its lines comes near. The
// margin covers the test's f32 rounding, whose error in `l` grows with the
// distance |f| from the centre, so that no line that meets the sphere is
// turned away.
bool line_near(vec3 o, vec3 d, vec3 c, float r2) {
    vec3 f = o - c;
    vec3 l = f - dot(f, d) * d;
    return dot(l, l) <= r2 * 1.0002 + 1.0e-6 * dot(f, f);
}

// `box_t` behind a test of the ray's line against the box's circumscribed
// sphere, which most rays miss: the test's branch skips the slab test (its
// rotation and six divisions) where no lane's line comes near the box.
float box_t_culled(vec3 o, vec3 d, BoxGeometry box, out vec2 face) {
    face = vec2(0.0);
    float t = 0.0;
    if (line_near(o, d, box.center, dot(box.half_extents, box.half_extents))) {
        t = box_t(o, d, box, face);
    }
    return t;
}

// Whether some lane's ray may meet something in the BVH: its line passes
// near the sphere around the whole tree (`frame.bvh_sphere`). Call in
// uniform control flow; a lane whose limit is negative asks nothing. A
// packet that may not skips the walk, and the divisions of its set-up: in
// a scene with a small mesh, most packets.
bool packet_near_bvh(vec3 o, vec3 d, float t_max) {
    vec4 sphere = frame.bvh_sphere;
    return packet_any(t_max >= 0.0 && sphere.w >= 0.0 && line_near(o, d, sphere.xyz, sphere.w * sphere.w));
}

// The outward normal of the face `box_t` hit: a column of the rotation.
vec3 box_normal(BoxGeometry box, vec2 face) {
    vec3 axis = face.x == 0.0 ? box.rotation[0] : (face.x == 1.0 ? box.rotation[1] : box.rotation[2]);
    return axis * face.y;
}

// The watertight test of Woop, Benthin and Wald (JCGT 2013), no culling:
// the twin of cpu::intersect::triangle, whose comment says why no ray slips
// between two triangles. `frame` is the ray's shear (ray_frame below).
struct RayFrame {
    uvec3 axes;     // kx, ky, kz
    vec3 origin;    // the ray's origin in that order
    vec3 shear;
};

RayFrame ray_frame(vec3 o, vec3 d) {
    vec3 a = abs(d);
    uint kz = (a.x >= a.y && a.x >= a.z) ? 0u : (a.y >= a.z ? 1u : 2u);
    uint kx = (kz + 1u) % 3u;
    uint ky = (kz + 2u) % 3u;
    if (d[kz] < 0.0) {
        uint swap = kx;
        kx = ky;
        ky = swap;
    }
    return RayFrame(uvec3(kx, ky, kz), vec3(o[kx], o[ky], o[kz]),
                    vec3(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]));
}

// Corner `v` of a shared triangle (read_triangle) relative to the ray's
// origin, sheared. The record holds the corners by axis, in consecutive
// quads from TRI_X (tests/shader_interface.rs holds TRI_Y and TRI_Z to
// that): axis k's quad is in lane TRI_X / 4 + k, its word v corner v's
// coordinate. So each coordinate in the order this lane's ray asks for is
// one shuffle whose source lane is the axis: picked from a corner's three
// coordinates per lane instead, they cost two selects each.
vec3 sheared_corner(Shared tri, uint v, RayFrame f) {
    const uint first = TRI_X / 4u;
    uint held = tri.q0[v];
    vec3 p = uintBitsToFloat(uvec3(subgroupShuffle(held, first + f.axes.x), subgroupShuffle(held, first + f.axes.y),
                                   subgroupShuffle(held, first + f.axes.z))) - f.origin;
    return vec3(p.x - f.shear.x * p.z, p.y - f.shear.y * p.z, f.shear.z * p.z);
}

// A triangle, shared by the subgroup (read_triangle), against this lane's
// ray (`frame`, from ray_frame): its t, or 0 for none, and the
// barycentrics of p1 and p2.
float triangle_t(RayFrame frame, Shared tri, out vec2 uv) {
    vec3 a = sheared_corner(tri, 0u, frame);
    vec3 b = sheared_corner(tri, 1u, frame);
    vec3 c = sheared_corner(tri, 2u, frame);
    // `precise`: a fused multiply-add would round one product and not the
    // other, and the neighbour's edge function would no longer be the exact
    // negative of this one.
    precise float u = c.x * b.y - c.y * b.x;
    precise float v = a.x * c.y - a.y * c.x;
    precise float w = b.x * a.y - b.y * a.x;
    bool inside = (u >= 0.0 && v >= 0.0 && w >= 0.0) || (u <= 0.0 && v <= 0.0 && w <= 0.0);
    float det = u + v + w;
    // The three divisions in a branch the driver skips when no lane's ray
    // crosses the triangle, as for most triangles a packet tests.
    float t = 0.0;
    uv = vec2(0.0);
    if (inside && det != 0.0) {
        uv = vec2(v, w) / det;
        t = (u * a.z + v * b.z + w * c.z) / det;
    }
    return t;
}

// The smaller and the larger of two numbers that are not NaN, as one
// comparison each: lavapipe's min() and max() also sort out a NaN operand,
// three instructions where this takes one.
float smaller(float a, float b) {
    return a < b ? a : b;
}

float larger(float a, float b) {
    return a > b ? a : b;
}

// Entry distance of the ray into a box (the slab test against [0, t_max]),
// or NO_HIT if it misses; a negative t_max misses every box. `inv_d` is
// finite (walk_bvh's `slab_inverse`), so no product here is NaN: for a
// zero direction component the slab test sorts that axis out (lo - o and
// hi - o of the same sign: no t at all; a ray inside the slab, or on one of
// its faces as the CPU twin counts it: all t).
float box_entry(vec3 o, vec3 inv_d, vec3 lo, vec3 hi, float t_max) {
    vec3 t1 = (lo - o) * inv_d;
    vec3 t2 = (hi - o) * inv_d;
    bvec3 t1_first = lessThan(t1, t2);
    vec3 t_in = mix(t2, t1, t1_first);
    vec3 t_out = mix(t1, t2, t1_first);
    float enter = larger(larger(t_in.x, t_in.y), larger(t_in.z, 0.0));
    float leave = smaller(smaller(t_out.x, t_out.y), smaller(t_out.z, t_max));
    return enter <= leave ? enter : NO_HIT;
}

// 1 / d for the slab test, with a zero component's infinity made the
// largest float: (lo - o) * inv_d is then never 0 * infinity (NaN) for a
// ray lying on a slab's face, and a product too large for a float is still
// an infinity of the right sign.
vec3 slab_inverse(vec3 d) {
    const float LARGEST = 3.4028235e38;
    return clamp(vec3(1.0) / d, vec3(-LARGEST), vec3(LARGEST));
}

#ifdef WIDE_BVH
// The wide step's moves (macros: the stack arrays stay the walk's own,
// where a function would copy them in and out). WIDE_STACK stacks a child
// if `cond`; WIDE_TAKE, for a child entered (`bit` set in `enters`), stacks
// the child taken so far and takes this one.
#define WIDE_STACK(cond, child, t)  \
    if (cond) {                     \
        stack_link[top] = child;    \
        stack_t[top] = t;           \
        ++top;                      \
    }
#define WIDE_TAKE(bit, child, t)                      \
    if ((enters & (bit)) != 0u) {                     \
        WIDE_STACK(link != NO_SHAPE, link, t_link)    \
        link = child;                                 \
        t_link = t;                                   \
    }

// Two children in the order of their keys (lane 0's entry distances).
void order_children(inout float ka, inout uint la, inout float ta, inout float kb, inout uint lb, inout float tb) {
    bool swap = kb < ka;
    float k = ka;
    uint l = la;
    float t = ta;
    ka = swap ? kb : ka;
    la = swap ? lb : la;
    ta = swap ? tb : ta;
    kb = swap ? k : kb;
    lb = swap ? l : lb;
    tb = swap ? t : tb;
}
#endif

// A hit on an analytic object in a BVH leaf: like `consider_object`, but
// `best` may be a triangle or an object found in another leaf, so a tie
// takes the general rule. For the shadow query (`any_hit`), any hit nearer
// than best.t ends the lane's search, as for triangles.
void consider_in_leaf(float t, uint shape, vec3 normal, float radius, uint material, uint object, bool any_hit,
                      inout Hit best) {
    if (any_hit) {
        if (t > 0.0 && t < best.t) {
            best = Hit(-1.0, shape, vec2(0.0), vec3(0.0), 0.0, 0u, 0u);
        }
    } else if (t > 0.0 && t <= best.t && (t < best.t || wins_tie(shape, best))) {
        best = Hit(t, shape, vec2(0.0), normal, radius, material, object);
    }
}

// The BVH's primitives (triangles, and the objects of long lists), the
// subgroup's rays as one packet (call in uniform control flow, and only
// where `packet_near_bvh` holds: some lane's ray may reach the tree). Each
// lane's ray takes part up to best.t (negative: not at all). A node is visited when any lane's ray enters its
// box within that lane's limit; of two children both entered, the one lane 0
// enters first goes first and the other waits on the stack with every
// lane's entry distance, to be skipped when popped if no lane can still
// find a nearer hit in it. A lane tests everything its own walk would have
// reached, and more, so its nearest hit (ties included) is what a walk of
// its own would give. Compiled with WIDE_BVH, a step tests a 4-wide node's
// children (rt_wide) the same way, the entered ones in the order lane 0
// enters them (a shadow query, which visits them all, in slot order).
//
// Nearest hit (`any_hit` false): best is the nearest hit. Shadow query
// (`any_hit`): a lane that finds a hit nearer than best.t stops there, its
// best.shape set and best.t made negative.
void walk_bvh(vec3 o, vec3 d, inout Hit best, bool any_hit) {
    uint link = frame.grid.w;  // the root: node 0, or a leaf
    vec3 inv_d = slab_inverse(d);
    RayFrame shear = ray_frame(o, d);
    // Cannot overflow: the host refuses a tree deeper than the stack
    // (rt_layout::BVH_STACK_SIZE), since a dropped node would be a miss,
    // and walks a tree 4-wide only where that walk's stack fits too
    // (rt_wide::WideBvh::stack_need).
    uint stack_link[BVH_STACK_SIZE];
    float stack_t[BVH_STACK_SIZE];
    int top = 0;
    // The caller's packet_near_bvh has already asked whether any lane has
    // a ray to trace.
    bool done = false;
    while (!done) {
        if ((link & LEAF_BIT) == 0u) {
#ifdef WIDE_BVH
            // Four children a step (rt_wide): their boxes, one butterfly
            // for which of them some lane enters (bit k: child k).
            Shared node = read_wide_node(link);
            float t0 = box_entry(o, inv_d, vec3_at(node, CHILD_LO), vec3_at(node, CHILD_HI), best.t);
            float t1 = box_entry(o, inv_d, vec3_at(node, CHILD_WORDS + CHILD_LO),
                                 vec3_at(node, CHILD_WORDS + CHILD_HI), best.t);
            float t2 = box_entry(o, inv_d, vec3_at(node, 2u * CHILD_WORDS + CHILD_LO),
                                 vec3_at(node, 2u * CHILD_WORDS + CHILD_HI), best.t);
            float t3 = box_entry(o, inv_d, vec3_at(node, 3u * CHILD_WORDS + CHILD_LO),
                                 vec3_at(node, 3u * CHILD_WORDS + CHILD_HI), best.t);
            uint l0 = word(node, CHILD_LINK);
            uint l1 = word(node, CHILD_WORDS + CHILD_LINK);
            uint l2 = word(node, 2u * CHILD_WORDS + CHILD_LINK);
            uint l3 = word(node, 3u * CHILD_WORDS + CHILD_LINK);
            uint enters = or_lanes((t0 != NO_HIT ? 1u : 0u) | (t1 != NO_HIT ? 2u : 0u) |
                                   (t2 != NO_HIT ? 4u : 0u) | (t3 != NO_HIT ? 8u : 0u));
            enters &= (l0 != NO_SHAPE ? 1u : 0u) | (l1 != NO_SHAPE ? 2u : 0u) | (l2 != NO_SHAPE ? 4u : 0u) |
                      (l3 != NO_SHAPE ? 8u : 0u);
            if (any_hit) {
                // A shadow query visits every entered child, in any
                // order: the first in slot order now, the others
                // stacked.
                link = NO_SHAPE;
                float t_link = 0.0;
                WIDE_TAKE(8u, l3, t3)
                WIDE_TAKE(4u, l2, t2)
                WIDE_TAKE(2u, l1, t1)
                WIDE_TAKE(1u, l0, t0)
            } else {
                // The entered children sorted by lane 0's entry
                // distance (as the binary step orders its two), the
                // nearest taken now and the others stacked, the
                // farthest deepest.
                const float NOT_ENTERED = 3.4e38;  // above NO_HIT
                float k0 = subgroupShuffle(t0, 0u);
                float k1 = subgroupShuffle(t1, 0u);
                float k2 = subgroupShuffle(t2, 0u);
                float k3 = subgroupShuffle(t3, 0u);
                k0 = (enters & 1u) != 0u ? k0 : NOT_ENTERED;
                k1 = (enters & 2u) != 0u ? k1 : NOT_ENTERED;
                k2 = (enters & 4u) != 0u ? k2 : NOT_ENTERED;
                k3 = (enters & 8u) != 0u ? k3 : NOT_ENTERED;
                order_children(k0, l0, t0, k1, l1, t1);
                order_children(k2, l2, t2, k3, l3, t3);
                order_children(k0, l0, t0, k2, l2, t2);
                order_children(k1, l1, t1, k3, l3, t3);
                order_children(k1, l1, t1, k2, l2, t2);
                uint entered = bitCount(enters);
                WIDE_STACK(entered > 3u, l3, t3)
                WIDE_STACK(entered > 2u, l2, t2)
                WIDE_STACK(entered > 1u, l1, t1)
                link = entered > 0u ? l0 : NO_SHAPE;  // none: pop below
            }
#else
            Shared node = read_node(link);
            float t_left = box_entry(o, inv_d, vec3_at(node, CHILD_LO), vec3_at(node, CHILD_HI), best.t);
            float t_right = box_entry(o, inv_d, vec3_at(node, CHILD_WORDS + CHILD_LO),
                                      vec3_at(node, CHILD_WORDS + CHILD_HI), best.t);
            uint left = word(node, CHILD_LINK);
            uint right = word(node, CHILD_WORDS + CHILD_LINK);
            // One butterfly for both children (bit 0: some lane enters the
            // left one, bit 1: the right one). The nearer child goes first
            // as lane 0 sees them, when lane 0 enters both: rays of a packet
            // are alike, and a vote would lengthen every step's critical
            // path by a second butterfly.
            uint enters = or_lanes((t_left != NO_HIT ? 1u : 0u) | (t_right != NO_HIT ? 2u : 0u));
            bool right_first = subgroupShuffle(t_right < t_left ? 1u : 0u, 0u) != 0u;
            bool enters_left = (enters & 1u) != 0u;
            bool enters_right = (enters & 2u) != 0u;
            if (enters_left && enters_right) {
                stack_link[top] = right_first ? left : right;
                stack_t[top] = right_first ? t_left : t_right;
                ++top;
                link = right_first ? right : left;
            } else if (enters_left) {
                link = left;
            } else if (enters_right) {
                link = right;
            } else {
                link = NO_SHAPE;  // pop below
            }
#endif
        } else {
            // A leaf: a run of one kind's records, the kind given by the
            // range its first index is in (uniform: the whole packet is here).
            uint first = link & 0x03ffffffu;
            uint end = first + ((link >> 26) & 31u) + 1u;
            if (first < frame.leaf_bases.x) {
                for (uint i = first; i < end; ++i) {
                    Shared tri = read_triangle(i);
                    vec2 uv;
                    float t = triangle_t(shear, tri, uv);
                    if (any_hit) {
                        if (t > 0.0 && t < best.t) {
                            best = Hit(-1.0, KIND_TRIANGLE | i, uv, vec3(0.0), 0.0, 0u, 0u);
                        }
                    } else {
                        consider_triangle(t, KIND_TRIANGLE | i, uv, best);
                    }
                }
            } else if (BVH_SPHERES && first < frame.leaf_bases.y) {
                for (uint i = first - frame.leaf_bases.x; i < end - frame.leaf_bases.x; ++i) {
                    SphereGeometry g = shared_sphere(i);
                    consider_in_leaf(sphere_t(o, d, g), KIND_SPHERE | i, g.center, g.radius, g.material, g.object,
                                     any_hit, best);
                }
            } else if (BVH_PLANES && first < frame.leaf_bases.z) {
                for (uint i = first - frame.leaf_bases.y; i < end - frame.leaf_bases.y; ++i) {
                    PlaneGeometry g = shared_plane(i);
                    consider_in_leaf(plane_t(o, d, g), KIND_PLANE | i, g.normal, 0.0, g.material, g.object, any_hit,
                                     best);
                }
            } else if (BVH_BOXES) {
                for (uint i = first - frame.leaf_bases.z; i < end - frame.leaf_bases.z; ++i) {
                    BoxGeometry g = shared_box(i);
                    vec2 face;
                    float t = box_t(o, d, g, face);
                    consider_in_leaf(t, KIND_BOX | i, box_normal(g, face), 0.0, g.material, g.object, any_hit, best);
                }
            }
            link = NO_SHAPE;
        }
        if (link == NO_SHAPE) {
            done = true;
            while (top > 0) {
                --top;
                if (packet_any(stack_t[top] <= best.t)) {
                    link = stack_link[top];
                    done = false;
                    break;
                }
            }
        }
    }
}

// The huge spheres, tested one by one by both engines (never in a BVH or
// an acceleration structure: they are few, and a box around one holds
// everything).
void consider_huge_spheres(vec3 o, vec3 d, inout Hit best) {
    for (int j = 0; j < HUGE_SPHERE_COUNT; ++j) {
        HugeSphere s = huge_sphere(j);
        uint record = frame.grid.z + 2u * uint(j);
        consider_object(huge_sphere_t(o, d, s), KIND_SPHERE | record, s.sphere.center, s.sphere.radius,
                        s.sphere.material, s.sphere.object, best);
    }
}

bool huge_sphere_blocks(vec3 o, vec3 d, float t_max) {
    bool blocked = false;
    for (int j = 0; j < HUGE_SPHERE_COUNT; ++j) {
        float t = huge_sphere_t(o, d, huge_sphere(j));
        blocked = blocked || (t > 0.0 && t < t_max);
    }
    return blocked;
}

#ifndef RAY_QUERY
// Every primitive against the ray: the nearest hit, ties to the lower
// object, then the lower triangle. Call in uniform control flow; a lane
// with no ray to trace passes `traces` false and gets no hit.
Hit nearest(vec3 o, vec3 d, bool traces) {
    Hit best = Hit(traces ? NO_HIT : -1.0, NO_SHAPE, vec2(0.0), vec3(0.0), 0.0, 0u, NO_SHAPE);
    for (int i = 0; i < SPHERE_COUNT; ++i) {
        SphereGeometry g = listed_spheres[i];
        consider_object(sphere_t(o, d, g), KIND_SPHERE | uint(i), g.center, g.radius, g.material, g.object, best);
    }
    consider_huge_spheres(o, d, best);
    for (int i = 0; i < PLANE_COUNT; ++i) {
        PlaneGeometry g = listed_planes[i];
        consider_object(plane_t(o, d, g), KIND_PLANE | uint(i), g.normal, 0.0, g.material, g.object, best);
    }
    for (int i = 0; i < BOX_COUNT; ++i) {
        BoxGeometry g = listed_boxes[i];
        vec2 face;
        float t = box_t_culled(o, d, g, face);
        consider_object(t, KIND_BOX | uint(i), box_normal(g, face), 0.0, g.material, g.object, best);
    }
    if (HAS_BVH && packet_near_bvh(o, d, best.t)) {
        walk_bvh(o, d, best, false);
    }
    if ((best.shape & KIND_MASK) == KIND_SPHERE) {
        // Once, for the nearest hit: a division per sphere tested cost more.
        best.normal = (o + best.t * d - best.normal) / best.radius;
    }
    return best;
}

// Whether anything is hit at 0 < t < t_max: the shadow-ray query, the twin
// of cpu::intersect::Accel::any. Call in uniform control flow; a negative
// t_max asks nothing. The BVH walk is bounded by t_max and ends for a lane
// at its first hit.
bool occluded(vec3 o, vec3 d, float t_max) {
    // The huge spheres first. Tested after the listed spheres, as
    // `nearest` does, the shadow rays of assets/hard/planet-light-below.toml
    // went through its planet on lavapipe 25.0.7 (with hits at 0 < t < 5
    // and t_max near 7.6, which the same source compiled into the
    // ray-query engine blocked): a difference we could not trace to the
    // source, which this order avoids (tests/hard_cases.rs holds it).
    bool blocked = huge_sphere_blocks(o, d, t_max);
    for (int i = 0; i < SPHERE_COUNT; ++i) {
        float t = sphere_t(o, d, listed_spheres[i]);
        blocked = blocked || (t > 0.0 && t < t_max);
    }
    for (int i = 0; i < PLANE_COUNT; ++i) {
        float t = plane_t(o, d, listed_planes[i]);
        blocked = blocked || (t > 0.0 && t < t_max);
    }
    for (int i = 0; i < BOX_COUNT; ++i) {
        vec2 face;
        float t = box_t_culled(o, d, listed_boxes[i], face);
        blocked = blocked || (t > 0.0 && t < t_max);
    }
    if (HAS_BVH && packet_near_bvh(o, d, blocked ? -1.0 : t_max)) {
        Hit best = Hit(blocked ? -1.0 : t_max, NO_SHAPE, vec2(0.0), vec3(0.0), 0.0, 0u, 0u);
        walk_bvh(o, d, best, true);
        blocked = blocked || best.shape != NO_SHAPE;
    }
    return blocked;
}
#else
#include "rt_query.glsl"
#endif

// What shading needs of the nearest hit, read once per ray.
struct Surfel {
    vec3 p;
    vec3 normal;     // shading normal (zero for a degenerate interpolation)
    vec3 geometric;  // unit geometric normal, for offsets
    uint material;
};

// (A kind the scene lacks is never hit, so its branch is never taken; a
// test of SPHERE_COUNT > 0 here would be an OpSpecConstantOp, which naga's
// SPIR-V reader rejects.)
Surfel resolve(vec3 o, vec3 d, Hit hit) {
    vec3 p = o + hit.t * d;
    uint index = hit.shape & ~KIND_MASK;
    uint kind = hit.shape & KIND_MASK;
    if (HAS_BVH && kind == KIND_TRIANGLE) {
        float bu = hit.uv.x;
        float bv = hit.uv.y;
        vec3 shading = (1.0 - bu - bv) * triangle_shading[index].n0 + bu * triangle_shading[index].n1
                       + bv * triangle_shading[index].n2;
        return Surfel(p, unit_or_zero(shading), triangle_shading[index].geometric,
                      triangle_shading[index].material);
    }
    return Surfel(p, hit.normal, hit.normal, hit.material);
}

// Texture coordinates at a hit: the f32 twin of src/scene/texcoords.rs,
// barycentric for a triangle.
vec2 hit_uv(Hit hit, Surfel s) {
    uint index = hit.shape & ~KIND_MASK;
    uint kind = hit.shape & KIND_MASK;
    if (HAS_BVH && kind == KIND_TRIANGLE) {
        vec2 b = hit.uv;
        return (1.0 - b.x - b.y) * triangle_uvs[index].uv01.xy + b.x * triangle_uvs[index].uv01.zw
               + b.y * triangle_uvs[index].uv2.xy;
    }
    if (kind == KIND_SPHERE) {
        // Longitude from +Z toward +X, colatitude from the top.
        const float TWO_PI = 6.28318530717958647692;
        vec3 n = s.normal;
        // The colatitude as atan(sin, cos), not acos(n.y): near the poles
        // acos of an f32 loses its digits (and lavapipe's acos more), where
        // an image's texels are narrowest.
        return vec2(0.5 + atan(n.x, n.z) / TWO_PI, atan(length(n.xz), n.y) / (0.5 * TWO_PI));
    }
    if (kind == KIND_PLANE) {
        // u along the plane's right, v down its image (its axes are right
        // and up).
        PlaneGeometry g = plane_geometry(int(index));
        vec3 offset = s.p - g.center;
        return vec2(dot(offset, g.u), -dot(offset, g.v)) / (2.0 * g.half_size) + 0.5;
    }
    // A box face: its axis is the normal's in the box's frame; its texture
    // axes are two of the box's axes, each either way, that the host chose
    // per face (texcoords::box_face_codes, in the record's last two words).
    BoxGeometry g = box_geometry(int(index));
    vec3 local = transpose(g.rotation) * s.normal;
    vec3 a = abs(local);
    int k = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    uint face = uint(2 * k) + (local[k] > 0.0 ? 1u : 0u);
    uvec4 record = box_quads[uint(index) * BOX_QUADS + BOX_FACE_U / 4u];
    uvec2 codes = (uvec2(record[BOX_FACE_U % 4u], record[BOX_FACE_V % 4u]) >> (3u * face)) & 7u;
    int ku = int(codes.x & 3u);
    int kv = int(codes.y & 3u);
    vec2 signs = mix(vec2(1.0), vec2(-1.0), notEqual(codes & 4u, uvec2(0u)));
    vec3 offset = s.p - g.center;
    return vec2(signs.x * dot(offset, g.rotation[ku]) / (2.0 * g.half_extents[ku]),
                -signs.y * dot(offset, g.rotation[kv]) / (2.0 * g.half_extents[kv])) + 0.5;
}

// Texels per unit of area of image `index` (its level 0, before its
// transform) on the surface at the hit: the twin of `surface_density` in
// src/cpu/surface.rs.
float hit_density(Hit hit, Surfel s, uint index) {
    uint shape = hit.shape & ~KIND_MASK;
    uint kind = hit.shape & KIND_MASK;
    float texels = texel_area(index);
    if (HAS_BVH && kind == KIND_TRIANGLE) {
        return texels * triangle_uvs[shape].uv2.z;
    }
    if (kind == KIND_SPHERE) {
        const float PI = 3.14159265358979323846;
        float r = sphere_geometry(int(shape)).radius;
        float sin_theta = length(s.normal.xz);
        return texels / (2.0 * PI * PI * r * r * sin_theta);
    }
    if (kind == KIND_PLANE) {
        float size = 2.0 * plane_geometry(int(shape)).half_size;
        return texels / (size * size);
    }
    BoxGeometry g = box_geometry(int(shape));
    vec3 a = abs(transpose(g.rotation) * s.normal);
    int k = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    return texels / (4.0 * g.half_extents[(k + 1) % 3] * g.half_extents[(k + 2) % 3]);
}

// The hit's material's pattern at the hit (1 without one): the twin of
// `pattern_color` in src/cpu/surface.rs. An image (TEXTURES) is read at the
// level of detail of the ray's cone, `cone_width` wide at the hit along
// `dir`. Called only with PATTERNS.
vec3 hit_pattern(Hit hit, Surfel s, vec3 dir, float cone_width) {
    vec4 a = patterns[s.material].checker_a;
    if (a.w == 0.0) {
        return vec3(1.0);
    }
    vec2 uv = hit_uv(hit, s);
    if (TEXTURES) {
        if (a.w < 0.0) {
            uint index = uint(-a.w) - 1u;
            vec3 b = patterns[s.material].checker_b.xyz;
            vec3 at = vec3(uv, 1.0);
            vec2 st = vec2(dot(a.xyz, at), dot(b, at));
            // How the transform scales areas.
            float det = abs(a.x * b.y - a.y * b.x);
            float density = hit_density(hit, s, index) * det;
            return sample_texture(index, st, cone_lambda(density, cone_width, dot(s.normal, dir)));
        }
    }
    vec2 cell = floor(a.w * uv);
    return mod(cell.x + cell.y, 2.0) == 0.0 ? a.rgb : patterns[s.material].checker_b.rgb;
}

// The vertex colour at a hit, interpolated like the normal: it multiplies
// the material's colour (docs/lighting-model.md, "Surface colour"). One
// off the meshes. Called only with VERTEX_COLORS.
vec3 hit_tint(Hit hit) {
    uint index = hit.shape & ~KIND_MASK;
    if (HAS_BVH && (hit.shape & KIND_MASK) == KIND_TRIANGLE) {
        float bu = hit.uv.x;
        float bv = hit.uv.y;
        return (1.0 - bu - bv) * triangle_colors[index].c0.rgb + bu * triangle_colors[index].c1.rgb
               + bv * triangle_colors[index].c2.rgb;
    }
    return vec3(1.0);
}

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
// faster.)
const int UNROLLED_MATERIALS = 8;
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

// One sample's ray tree, in the order of docs/raytracing.md: the tree is
// walked depth first with the refracted child before the reflected one. The
// ray in hand goes on to its first child; only a reflected ray whose
// sibling is refracted waits on the stack. The subgroup goes on while any
// lane has a ray (the walks are packets); `live` says whether this one has.
vec3 trace_sample(vec3 dir, bool live) {
    Ray waiting[STACK_SIZE];
    // Each ray's cone (an image's level of detail): its width at the
    // origin and its growth per unit of distance. Kept beside the rays and
    // touched only with TEXTURES, so that a scene without images carries
    // none of it (its pipeline compiled as fast as before them).
    vec2 waiting_cones[STACK_SIZE];
    int top = 0;
    Ray ray = Ray(vec3(0.0), dir, 1.0, 0);
    vec2 cone = vec2(0.0);
    if (TEXTURES) {
        // A primary cone widens by a pixel's height per unit of distance
        // (level_of_detail::pixel_spread).
        cone.y = 2.0 / (frame.right_focal.w * float(frame.image.y));
    }
    if (live) {
        count(0);
    }
    vec3 total = vec3(0.0);
    int max_depth = int(frame.image.w);
    float cutoff = frame.forward_cutoff.w;
    // The first search without a vote: a packet with no pixel on the
    // image is rare (the image's edges), and its lanes find nothing.
    bool packet_goes_on = true;
    while (packet_goes_on) {
        if (live) {
            deepest = max(deepest, ray.depth);
        }
        Hit hit = nearest(ray.origin, ray.dir, live);
        bool hits = live && hit.shape != NO_SHAPE;
        if (live && !hits) {
            total += ray.weight * frame.background.rgb;
        }
        Surfel s = Surfel(vec3(0.0), vec3(0.0), vec3(0.0), 0u);
        MaterialRecord material = MaterialRecord(vec4(0.0), vec4(0.0), vec2(0.0));
        vec3 local = vec3(0.0);
        // Shading walks shadow rays as packets: the whole subgroup comes
        // here, or none of it (where every ray left the scene). With no
        // BVH nothing below shuffles, so each lane goes its own way and
        // the driver's masks do what the votes did, for less (a vote is
        // three shuffles; the four spheres took 0.9x the time without).
        bool packet_hits = HAS_BVH ? packet_any(hits) : hits;
        if (packet_hits) {
            if (hits) {
                s = resolve(ray.origin, ray.dir, hit);
            }
            material = material_at(s.material);
            Surface surface = surface_of(material);
            if (VERTEX_COLORS) {
                if (hits) {
                    surface.color *= hit_tint(hit);
                }
            }
            if (PATTERNS) {
                if (hits) {
                    surface.color *= hit_pattern(hit, s, ray.dir, cone.x + cone.y * hit.t);
                }
            }
            local = local_shading(s, surface, ray.origin, ray.dir, hits);
        }
        live = false;
        if (hits) {
            total += ray.weight * local;
            // Specialization constants appear only as whole conditions: naga's
            // SPIR-V reader rejects operators on them (OpSpecConstantOp).
            bool may_branch = false;
            if (HAS_REFLECTION) {
                // No children from a zero normal: no direction to reflect
                // or refract about.
                may_branch = ray.depth < max_depth && s.normal != vec3(0.0);
            }
            if (may_branch) {
                float kr = material.kd_ks_p_kr.w;
                vec3 N = s.normal;
                // Decided by kr and total internal reflection, not by the
                // weight, as on the CPU: a weight that underflows in f32 is
                // still a child (pruned).
                bool reflects = kr > 0.0;
                float reflect_weight = ray.weight * kr;
                bool refracts = false;
                vec3 refract_dir = vec3(0.0);
                float refract_weight = 0.0;
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
                            reflects = true;  // total internal reflection
                            reflect_weight = ray.weight * (kr + kt);
                        } else {
                            refracts = true;
                            refract_dir = normalize(eta * along - sqrt(k) * n);
                            refract_weight = ray.weight * kt;
                        }
                    }
                }
                if (reflects && reflect_weight < cutoff) {
                    reflects = false;
                    count(4);
                }
                if (refracts && refract_weight < cutoff) {
                    refracts = false;
                    count(4);
                }
                // The children's cones start as wide as this one at the hit;
                // a mirror sphere spreads its reflection by 2 w / r more
                // (its curvature), flat surfaces and refraction do not.
                vec2 refracted_cone = vec2(0.0);
                vec2 reflected_cone = vec2(0.0);
                if (TEXTURES) {
                    float width = cone.x + cone.y * hit.t;
                    float curvature = 0.0;
                    if ((hit.shape & KIND_MASK) == KIND_SPHERE) {
                        curvature = 2.0 * width / sphere_geometry(int(hit.shape & ~KIND_MASK)).radius;
                    }
                    refracted_cone = vec2(width, cone.y);
                    reflected_cone = vec2(width, cone.y + curvature);
                }
                Ray reflected;
                if (reflects) {
                    vec3 r = ray.dir - 2.0 * dot(ray.dir, N) * N;
                    reflected = Ray(offset_origin(s.p, ray.origin, s.geometric, r), r, reflect_weight, ray.depth + 1);
                    count(2);
                }
                if (refracts) {
                    if (reflects) {
                        if (TEXTURES) {
                            waiting_cones[top] = reflected_cone;
                        }
                        waiting[top++] = reflected;
                    }
                    ray = Ray(offset_origin(s.p, ray.origin, s.geometric, refract_dir), refract_dir, refract_weight,
                              ray.depth + 1);
                    if (TEXTURES) {
                        cone = refracted_cone;
                    }
                    count(3);
                    live = true;
                } else if (reflects) {
                    ray = reflected;
                    if (TEXTURES) {
                        cone = reflected_cone;
                    }
                    live = true;
                }
            }
        }
        if (HAS_TRANSMISSION && !live && top > 0) {
            ray = waiting[--top];
            if (TEXTURES) {
                cone = waiting_cones[top];
            }
            live = true;
        }
        // Without refraction no ray waits, so where nothing was hit the
        // packet is done, and a miss costs one vote, not two. Without a
        // BVH, no vote (above).
        if (HAS_BVH) {
            if (HAS_TRANSMISSION) {
                packet_goes_on = packet_any(live);
            } else {
                packet_goes_on = packet_hits && packet_any(live);
            }
        } else {
            packet_goes_on = live;
        }
    }
    return total;
}

void main() {
    // Subgroups take work items from a queue (one atomic counter) until it
    // runs dry, so the image's pixels are shared out as the work goes, not
    // by workgroup id: lavapipe hands each of its threads a fixed share of
    // the workgroups, and a thread that was slower (a busier core, or the
    // share of the image with the scene in it) left the others idle at the
    // end. An item is 16 packets, each packet a 4 x (S/4) patch of
    // pixels for a subgroup of S lanes (4 x 2 on lavapipe): 16 x S pixels,
    // in rows of items from the top. Each lane's colour depends on its own
    // ray alone (see walk_bvh), so which subgroup traces a pixel, and with
    // which neighbours, leaves the image as it is.
    uint lane = gl_SubgroupInvocationID;
    uint size = gl_SubgroupSize;
    uvec2 in_patch = uvec2(lane & 3u, lane >> 2);
    uint rows_per_patch = size >> 2;
    uint width = frame.image.x;
    uint height = frame.image.y;
    for (int k = 0; k < 5; ++k) {
        local_counts[k] = 0u;
    }
#ifndef RAY_QUERY
    read_listed_objects();
#endif
    if (MATERIALS_LISTED) {
        read_listed_materials();
    }
    // The host holds the count to 1..1024; at least 1 here all the same,
    // as the sample loop below runs once before it tests the count.
    uint samples = max(frame.image.z, 1u);
    float kx = float(frame.grid.x);
    // The camera's divisions, once per invocation: per pixel they were a
    // chain of dependent divisions at the start of every ray, about a tenth
    // of a small scene's time (profiled on assets/rt-mesh.toml). Products
    // with reciprocals round differently from the quotients by an ulp at
    // most, as the f32 quotients already differ from the reference's f64.
    float inv_kx = 1.0 / kx;
    float inv_ky = 1.0 / float(frame.grid.y);
    vec2 ndc_per_pixel = vec2(2.0 / float(width), 2.0 / float(height));
    float inv_focal = 1.0 / frame.right_focal.w;
    vec3 right_per_ndc = frame.right_focal.xyz * (frame.up_aspect.w * inv_focal);
    vec3 up_per_ndc = frame.up_aspect.xyz * inv_focal;
    uint items_across = (width + ITEM_WIDTH - 1u) / ITEM_WIDTH;
    uint item_count = items_across * ((height + size - 1u) / size);
    for (;;) {
        // Uniform control flow: lane 0 takes the item, every lane gets it.
        uint item = 0u;
        if (lane == 0u) {
            item = atomicAdd(next_item, 1u);
        }
        item = subgroupShuffle(item, 0u);
        if (item >= item_count) {
            break;
        }
        uvec2 origin = uvec2(item % items_across * ITEM_WIDTH, item / items_across * size);
        for (uint b = 0u; b < ITEM_PACKETS; ++b) {
            uvec2 pixel = origin + uvec2((b & 3u) * 4u, (b >> 2) * rows_per_patch) + in_patch;
            // No early return: the lanes of a pixel off the image still take
            // part in their subgroup's packets, with nothing to trace.
            bool on_image = pixel.x < width && pixel.y < height;
            vec3 sum = vec3(0.0);
            // At least one sample (`samples` above), so the test ends the
            // loop rather than opening it: written the other way,
            // with the count tested first, the small scenes took 1.1x to
            // 1.3x the time on lavapipe (four spheres 1.2x; 24 to 50 runs
            // of each shader alternated in one process), the images the
            // same.
            for (uint i = 0u;;) {
                // Sample i's cell: row i / kx and column i % kx, in floats
                // (exact for any sample count the host allows: (i + 0.5) / kx
                // is at least 0.5 / kx from an integer, far more than a
                // rounding).
                float row = floor((float(i) + 0.5) * inv_kx);
                float column = float(i) - row * kx;
                vec2 cell = vec2(column + 0.5, row + 0.5) * vec2(inv_kx, inv_ky);
                vec2 ndc = (vec2(pixel) + cell) * ndc_per_pixel - 1.0;
                vec3 dir = frame.forward_cutoff.xyz + right_per_ndc * ndc.x - up_per_ndc * ndc.y;
                sum += trace_sample(dir * inversesqrt(dot(dir, dir)), on_image);
                if (++i >= samples) {
                    break;
                }
            }
            if (on_image) {
                pixels[pixel.y * width + pixel.x] = vec4(sum / float(samples), 1.0);
            }
        }
    }
    if (COUNT_RAYS) {
        for (int k = 0; k < 5; ++k) {
            if (local_counts[k] > 0u) {
                atomicAdd(counters[k], local_counts[k]);
            }
        }
        atomicMax(counters[5], uint(deepest));
    }
}
