// The ray tracer's surface at the nearest hit, read once per ray after the
// search: position, normals and material, texture coordinates, the
// pattern's or image's colour, the vertex colour.
#ifndef RT_SURFACE_GLSL
#define RT_SURFACE_GLSL

#include "rt_interface.glsl"
#include "lighting.glsl"
#include "texture.glsl"
#include "rt_ray.glsl"
#include "rt_objects.glsl"

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

#endif
