// The interface between the host and the ray-tracing compute shader:
// specialization constants, descriptor bindings, buffer records. The host's
// side is src/gpu/rt_layout.rs; tests/shader_interface.rs checks the two
// agree. Positions are camera-relative (the eye is the origin), computed in
// double precision on the host (src/rt_scene.rs).

// Shared with the raster pipelines (same ids, same meaning).
#include "lights.glsl"

// What the scene uses; what it does not is compiled out.
layout(constant_id = 3) const bool SHADOWS = true;
layout(constant_id = 4) const bool HAS_REFLECTION = true;    // kr > 0 or kt > 0 somewhere
layout(constant_id = 5) const bool HAS_TRANSMISSION = true;  // kt > 0 somewhere
layout(constant_id = 6) const bool HAS_SPHERES = true;
layout(constant_id = 7) const bool HAS_PLANES = true;
layout(constant_id = 8) const bool HAS_BOXES = true;
layout(constant_id = 9) const bool HAS_MESHES = true;
// Ray statistics with atomics, only when asked for (--stats).
layout(constant_id = 10) const bool COUNT_RAYS = false;

layout(std140, set = 0, binding = 1) uniform TraceUniforms {
    vec4 ambient_k;       // rgb: Ia, w: k
    vec4 background;      // rgb
    vec4 right_focal;     // xyz: camera right, w: 1 / tan(fov_y / 2)
    vec4 up_aspect;       // xyz: camera up, w: width / height
    vec4 forward_cutoff;  // xyz: camera forward, w: the cut-off weight
    uvec4 image;          // x: width, y: height, z: samples, w: maximum depth
    uvec4 grid;           // x, y: the sample grid kx, ky
    uvec4 counts;         // spheres, planes, boxes, triangles
} frame;

struct Sphere {
    vec4 center_radius;
    uvec4 material_object;
};

struct Plane {
    vec4 center_half;  // xyz: centre, w: half the edge length
    vec4 normal;
    vec4 u;
    vec4 v;
    uvec4 material_object;
};

struct Box {
    vec4 center;
    vec4 half_extents;
    vec4 axis_x;  // the columns of the box's rotation
    vec4 axis_y;
    vec4 axis_z;
    uvec4 material_object;
};

struct Triangle {
    vec4 p0;
    vec4 p1;
    vec4 p2;
    vec4 n0;
    vec4 n1;
    vec4 n2;
    uvec4 material_object;
};

struct BvhNode {
    vec3 lo;
    uint prim_count;  // 0: inner node, children at first and first + 1
    vec3 hi;
    uint first;       // leaf: first entry in `primitive_indices`
};

struct RtMaterial {
    vec4 color_ka;
    vec4 kd_ks_p_kr;
    vec4 kt_ior;
};

layout(std430, set = 0, binding = 2) readonly buffer SphereBuffer { Sphere spheres[]; };
layout(std430, set = 0, binding = 3) readonly buffer PlaneBuffer { Plane planes[]; };
layout(std430, set = 0, binding = 4) readonly buffer BoxBuffer { Box boxes[]; };
layout(std430, set = 0, binding = 5) readonly buffer TriangleBuffer { Triangle triangles[]; };
layout(std430, set = 0, binding = 6) readonly buffer BvhBuffer { BvhNode nodes[]; };
layout(std430, set = 0, binding = 7) readonly buffer PrimitiveBuffer { uint primitive_indices[]; };
layout(std430, set = 0, binding = 8) readonly buffer MaterialBuffer { RtMaterial materials[]; };
// Not `writeonly`: naga does not accept write-only storage buffers.
layout(std430, set = 0, binding = 9) buffer OutputBuffer { vec4 pixels[]; };
// primary, shadow, reflected, refracted, pruned, deepest level, 2 unused.
layout(std430, set = 0, binding = 10) buffer StatsBuffer { uint counters[8]; };
