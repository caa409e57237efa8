// The ray tracer's analytic objects (spheres, planes, boxes) read from
// their records, and the listed ones read once per invocation.
#ifndef RT_OBJECTS_GLSL
#define RT_OBJECTS_GLSL

#include "kernel_sizes.glsl"
#include "rt_interface.glsl"
#include "rt_packet.glsl"

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
// with them read once. Sized as kernel_sizes::UNROLLED_* (longer lists go
// into the BVH).
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

#endif
