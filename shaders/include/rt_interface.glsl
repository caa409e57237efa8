// The interface between the host and the ray-tracing compute shader:
// specialization constants, descriptor bindings, buffer records. The host's
// side is src/gpu/raytrace/layout.rs (records built in src/gpu/raytrace/records.rs);
// tests/cpu/shader_interface.rs checks the two agree. Positions are
// camera-relative (the eye is the origin), computed in double precision on
// the host (src/rt_scene/).
//
// The records are laid out for lavapipe, where every buffer read at an
// index that differs between invocations costs a scalar load per lane and
// per 4-byte component (docs/raytracing.md, "Why the shader is shaped this
// way"): the BVH stores both children's boxes in their parent, so one read
// of a node tests both; triangles are stored in BVH leaf order with only
// what the intersection test needs, and what shading needs sits in a
// second record read once per ray, for the nearest hit. Nodes, triangles
// and object records are read as quads of words, so that a subgroup can
// share them.
#ifndef RT_INTERFACE_GLSL
#define RT_INTERFACE_GLSL

// Shared with the raster pipelines (same ids, same meaning).
#include "lights.glsl"

// What the scene uses; what it does not is compiled out.
layout(constant_id = 3) const bool SHADOWS = true;
layout(constant_id = 4) const bool HAS_REFLECTION = true;    // kr > 0 or kt > 0 somewhere
layout(constant_id = 5) const bool HAS_TRANSMISSION = true;  // kt > 0 somewhere
// Counts of the objects tested one by one, by kind: loops over them have a
// trip count known when the pipeline is built, so the driver unrolls them
// and every record is read at a constant index (one load for all
// invocations). A list too long to unroll goes into the BVH instead
// (gpu::raytrace::bvh::BvhKinds), and its count here is 0.
layout(constant_id = 6) const int SPHERE_COUNT = 0;
layout(constant_id = 7) const int PLANE_COUNT = 0;
layout(constant_id = 8) const int BOX_COUNT = 0;
// Whether there is a BVH to walk (mesh triangles, long object lists).
layout(constant_id = 9) const bool HAS_BVH = true;
// Ray statistics with atomics, only when asked for (--stats).
layout(constant_id = 10) const bool COUNT_RAYS = false;
// The kinds of analytic object the BVH holds.
layout(constant_id = 11) const bool BVH_SPHERES = false;
layout(constant_id = 12) const bool BVH_PLANES = false;
layout(constant_id = 13) const bool BVH_BOXES = false;
// Whether the scene's materials are few enough to be read once per
// invocation and picked by selects (kernel_sizes::UNROLLED_MATERIALS), and
// then how many there are; otherwise each lane reads its own.
layout(constant_id = 14) const bool MATERIALS_LISTED = false;
layout(constant_id = 15) const int MATERIAL_COUNT = 0;
// Whether some mesh has vertex colours (`triangle_colors` below).
layout(constant_id = 16) const bool VERTEX_COLORS = false;
// Whether some material has a pattern (`patterns`, `triangle_uvs` below).
layout(constant_id = 17) const bool PATTERNS = false;
// Whether some pattern is an image (`texture_records`, `texels` below).
layout(constant_id = 18) const bool TEXTURES = false;
// Where every image has one sampler: its bits (texture.glsl).
layout(constant_id = 19) const bool SAMPLER_FIXED = false;
layout(constant_id = 20) const uint FIXED_SAMPLER = 0u;
// Spheres tested from their anchor (src/huge_sphere.rs): two records each
// in `sphere_quads`, from `frame.grid.z` on; never in a BVH.
layout(constant_id = 21) const int HUGE_SPHERE_COUNT = 0;

layout(std140, set = 0, binding = 1) uniform TraceUniforms {
    vec4 ambient_k;       // rgb: Ia, w: k
    vec4 background;      // rgb
    vec4 right_focal;     // xyz: camera right, w: 1 / tan(fov_y / 2)
    vec4 up_aspect;       // xyz: camera up, w: width / height
    vec4 forward_cutoff;  // xyz: camera forward, w: the cut-off weight
    uvec4 image;          // x: width, y: height, z: samples, w: maximum depth
    uvec4 grid;           // x, y: the sample grid kx, ky; z: the first huge sphere's record; w: the BVH's root link
    // x, y, z: the BVH leaf index of its first sphere, plane and box (its
    // triangles start at 0; a leaf's kind is the range its first index is
    // in); w: the diffuse bounces a path may take (read with PATHS)
    uvec4 leaf_bases;
    // xyz: centre, w: radius of a sphere around the whole BVH (negative for
    // an empty tree)
    vec4 bvh_sphere;
} frame;

// Object records, read as quads of words (like nodes and triangles below):
// rt_layout::GpuSphere, GpuPlane and GpuBox, with these word offsets.
const uint SPHERE_QUADS = 2u;
const uint SPHERE_CENTER = 0u;
const uint SPHERE_RADIUS = 3u;
const uint SPHERE_MATERIAL = 4u;
const uint SPHERE_OBJECT = 5u;

const uint PLANE_QUADS = 5u;
const uint PLANE_CENTER = 0u;
const uint PLANE_HALF = 3u;  // half the edge length
const uint PLANE_NORMAL = 4u;
const uint PLANE_U = 8u;
const uint PLANE_V = 12u;
const uint PLANE_MATERIAL = 16u;
const uint PLANE_OBJECT = 17u;

const uint BOX_QUADS = 6u;
const uint BOX_CENTER = 0u;
const uint BOX_HALF = 4u;
const uint BOX_AXIS_X = 8u;  // the columns of the box's rotation
const uint BOX_AXIS_Y = 12u;
const uint BOX_AXIS_Z = 16u;
const uint BOX_MATERIAL = 20u;
const uint BOX_OBJECT = 21u;
// Each face's texture axes, 3 bits a face (texcoords::box_face_codes).
const uint BOX_FACE_U = 22u;
const uint BOX_FACE_V = 23u;

// What the intersection test reads of a triangle, in BVH leaf order: 3
// quads of words (rt_layout::GpuTriangleGeometry), so that the lanes of a
// subgroup can share them (rt_packet.glsl, `Shared`), one per axis:
// quad k holds coordinate k of the corners p0, p1 and p2, and one more
// word: `index`, the triangle's place in the scene's triangle list
// (rt_scene::RtScene), which the tie rule compares; `object`, its scene
// object. Word offsets:
const uint TRI_QUADS = 3u;
const uint TRI_X = 0u;  // p0.x, p1.x, p2.x
const uint TRI_INDEX = 3u;
const uint TRI_Y = 4u;
const uint TRI_OBJECT = 7u;
const uint TRI_Z = 8u;

// What shading reads of the nearest hit's triangle, in the same order.
struct TriangleShading {
    vec3 n0;
    uint material;
    vec3 n1;
    uint unused1;
    vec3 n2;
    uint unused2;
    vec3 geometric;  // unit geometric normal (f64 on the host), for offsets
    uint unused3;
};

// An inner node of the BVH holds its children's boxes and links, each
// child CHILD_WORDS words (rt_layout::GpuBvhChild), read like triangles: a
// binary node two children (NODE_QUADS quads of words, rt_layout::GpuBvhNode);
// a 4-wide node, walked by the variant compiled with WIDE_BVH defined (a
// big tree, rt_wide), four (WIDE_NODE_QUADS, rt_layout::GpuWideNode), the
// used slots first, an empty one's link NO_SHAPE. A child link is a node
// index, or for a leaf LEAF_BIT | its primitive count less one in bits 26
// to 30 and its first leaf index below (`frame.leaf_bases`). The root's
// link is in the uniforms (a mesh of a few triangles is one leaf).
const uint CHILD_WORDS = 8u;
const uint CHILD_LO = 0u;
const uint CHILD_LINK = 3u;
const uint CHILD_HI = 4u;
const uint NODE_QUADS = 4u;
const uint WIDE_NODE_QUADS = 8u;

const uint LEAF_BIT = 0x80000000u;

struct RtMaterial {
    vec4 color_ka;
    vec4 kd_ks_p_kr;
    vec4 kt_ior;
};

layout(std430, set = 0, binding = 2) readonly buffer SphereBuffer { uvec4 sphere_quads[]; };
layout(std430, set = 0, binding = 3) readonly buffer PlaneBuffer { uvec4 plane_quads[]; };
layout(std430, set = 0, binding = 4) readonly buffer BoxBuffer { uvec4 box_quads[]; };
layout(std430, set = 0, binding = 5) readonly buffer TriangleGeometryBuffer { uvec4 triangle_quads[]; };
layout(std430, set = 0, binding = 6) readonly buffer BvhBuffer { uvec4 node_quads[]; };
layout(std430, set = 0, binding = 7) readonly buffer TriangleShadingBuffer { TriangleShading triangle_shading[]; };
layout(std430, set = 0, binding = 8) readonly buffer MaterialBuffer { RtMaterial materials[]; };
#ifdef FORWARD
// The forward tracer's film (forward.comp.glsl): each pixel's red, green
// and blue sums of splats in fixed point, FILM_ONE to 1.0, added with
// 64-bit atomics, so that the sums do not depend on the order the photons
// land in (gpu::raytrace::forward::film).
layout(std430, set = 0, binding = 9) buffer FilmBuffer { uint64_t film[]; };
// Photons emitted, splats that landed, photons seen, surfaces hit.
layout(std430, set = 0, binding = 10) buffer PhotonCountBuffer { uint64_t photon_counts[4]; };
#else
#ifdef PATHS
// With diffuse bounces, each pixel's red, green and blue sums of its
// samples in fixed point, two words each (rt_sample_sums.glsl), added to
// by each dispatch of a range of samples.
layout(std430, set = 0, binding = 9) buffer SampleSumBuffer { uvec2 sample_sums[]; };
// The samples this dispatch traces, of the frame.image.z each pixel has
// (gpu::raytrace::layout::SampleRange): first, first + step, ... below end;
// first < end. A step of 2 traces one of the two streams of samples
// (rt_pixel_samples.glsl), as --error's halves need.
layout(push_constant) uniform SampleRange {
    uint first;
    uint end;
    uint step;
    uint unused;
} sample_range;
#else
// Not `writeonly`: naga does not accept write-only storage buffers.
layout(std430, set = 0, binding = 9) buffer OutputBuffer { vec4 pixels[]; };
#endif
// primary, shadow, reflected, refracted, pruned, deepest level, 2 unused.
layout(std430, set = 0, binding = 10) buffer StatsBuffer { uint counters[8]; };
#endif
// Each triangle's vertex colours, in the order of `triangle_shading`
// (rt_layout::GpuTriangleColors), read only with VERTEX_COLORS.
struct TriangleColors {
    vec4 c0;
    vec4 c1;
    vec4 c2;
};
layout(std430, set = 0, binding = 12) readonly buffer TriangleColorBuffer { TriangleColors triangle_colors[]; };
// Each triangle's texture coordinates, likewise (rt_layout::GpuTriangleUvs),
// and each material's pattern (rt_layout::GpuPattern), read only with
// PATTERNS.
struct TriangleUvs {
    vec4 uv01;  // xy: corner 0, zw: corner 1
    vec4 uv2;   // xy: corner 2, z: uv area per unit of world area
};
struct MaterialPattern {
    vec4 checker_a;  // rgb: first colour, w: scale (0: no pattern; -1 - index:
                     // image `index`, its uv transform's rows in the two xyz)
    vec4 checker_b;  // rgb: second colour
};
layout(std430, set = 0, binding = 13) readonly buffer TriangleUvBuffer { TriangleUvs triangle_uvs[]; };
layout(std430, set = 0, binding = 14) readonly buffer PatternBuffer { MaterialPattern patterns[]; };
// The image textures (gpu::texture_table), read by texture.glsl only with
// TEXTURES.
layout(std430, set = 0, binding = 15) readonly buffer TextureRecordBuffer { uvec4 texture_records[]; };
layout(std430, set = 0, binding = 16) readonly buffer TexelBuffer { vec4 texels[]; };
// The work queue: the next work item to take (zeroed before each dispatch;
// rt_work_queue.glsl).
layout(std430, set = 0, binding = 11) buffer WorkQueueBuffer { uint next_item; };

#endif
