#version 460
#extension GL_GOOGLE_include_directive : require
// Backward (Whitted) ray tracing, one invocation per pixel, exactly as
// docs/raytracing.md specifies (its CPU twin is src/cpu/raytrace.rs):
// stratified samples, nearest hits with the object-order tie rule, shadow
// rays, reflection and refraction with total internal reflection.
//
// Shaped for lavapipe, which runs 8 invocations in the lanes of one SIMD
// register: a branch costs what the union of its lanes' paths costs, a loop
// runs until its slowest lane is done, and a buffer read at an index that
// differs between lanes costs a scalar load per lane and component
// (docs/raytracing.md, "Why the shader is shaped this way"). So the inner
// loops read as little as they can, and whatever only the nearest hit needs
// (normals, material) is read once, after the search.

// 64 invocations: 8 subgroups of 8 lanes, each a 4x2 block of an 8x8 tile.
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

#include "rt_interface.glsl"
#include "lighting.glsl"

// Depth is at most 64 (checked on the host). Only a ray that both reflects
// and refracts leaves a ray waiting, one per level.
const int STACK_SIZE = 64;
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

// The nearest hit so far: only what the search compares. Normals and the
// material are looked up once the search is over (`resolve`).
struct Hit {
    float t;
    uint shape;  // KIND_* | index, or NO_SHAPE
    vec2 uv;     // triangle: barycentrics of p1 and p2; box: axis, sign
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

// The scene object of a shape, and its place among that object's
// primitives (triangles only), for the tie rule.
uint object_of(uint shape) {
    uint index = shape & ~KIND_MASK;
    switch (shape & KIND_MASK) {
        case KIND_SPHERE:
            return spheres[index].material_object.y;
        case KIND_PLANE:
            return planes[index].material_object.y;
        case KIND_BOX:
            return boxes[index].material_object.y;
        default:
            return triangles[index].object;
    }
}

uint order_of(uint shape) {
    return (shape & KIND_MASK) == KIND_TRIANGLE ? triangles[shape & ~KIND_MASK].index : 0u;
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

// Makes a hit at t the nearest if it is (t > 0, then the tie rule).
void consider(float t, uint shape, vec2 uv, inout Hit best) {
    if (t > 0.0 && t <= best.t && (t < best.t || wins_tie(shape, best))) {
        best = Hit(t, shape, uv);
    }
}

// Distance to sphere i along the ray, or 0 for none (the stable form).
float sphere_t(vec3 o, vec3 d, int i) {
    vec3 c = spheres[i].center_radius.xyz;
    float r = spheres[i].center_radius.w;
    vec3 f = o - c;
    float b = -dot(f, d);
    vec3 l = f + b * d;
    float disc = r * r - dot(l, l);
    if (disc < 0.0) {
        return 0.0;
    }
    float q = b + (b >= 0.0 ? 1.0 : -1.0) * sqrt(disc);
    if (q == 0.0) {
        return 0.0;
    }
    float t0 = (dot(f, f) - r * r) / q;
    float t1 = q;
    return min(t0, t1) > 0.0 ? min(t0, t1) : max(t0, t1);
}

float plane_t(vec3 o, vec3 d, int i) {
    vec3 c = planes[i].center_half.xyz;
    vec3 n = planes[i].normal.xyz;
    float denom = dot(d, n);
    if (denom == 0.0) {
        return 0.0;
    }
    float t = dot(c - o, n) / denom;
    vec3 rel = o + t * d - c;
    float h = planes[i].center_half.w;
    bool inside = abs(dot(rel, planes[i].u.xyz)) <= h && abs(dot(rel, planes[i].v.xyz)) <= h;
    return inside ? t : 0.0;
}

// Distance to box i, or 0; `face` gets the axis of the face hit and the
// sign of its outward normal (box-local).
float box_t(vec3 o, vec3 d, int i, out vec2 face) {
    mat3 rot = mat3(boxes[i].axis_x.xyz, boxes[i].axis_y.xyz, boxes[i].axis_z.xyz);
    vec3 h = boxes[i].half_extents.xyz;
    vec3 lo = transpose(rot) * (o - boxes[i].center.xyz);
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

// The watertight test of Woop, Benthin and Wald (JCGT 2013), no culling:
// the twin of cpu::intersect::triangle, whose comment says why no ray slips
// between two triangles. `frame` is the ray's shear (ray_frame below).
struct RayFrame {
    ivec3 axes;
    vec3 shear;
};

RayFrame ray_frame(vec3 d) {
    vec3 a = abs(d);
    int kz = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
    int kx = (kz + 1) % 3;
    int ky = (kz + 2) % 3;
    if (d[kz] < 0.0) {
        int swap = kx;
        kx = ky;
        ky = swap;
    }
    return RayFrame(ivec3(kx, ky, kz), vec3(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]));
}

vec3 sheared(RayFrame f, vec3 p) {
    return vec3(p[f.axes.x] - f.shear.x * p[f.axes.z], p[f.axes.y] - f.shear.y * p[f.axes.z],
                f.shear.z * p[f.axes.z]);
}

// Triangle i (leaf order) against the ray: its t, or 0 for none, and the
// barycentrics of p1 and p2.
float triangle_t(vec3 o, RayFrame frame, uint i, out vec2 uv) {
    vec3 a = sheared(frame, triangles[i].p0 - o);
    vec3 b = sheared(frame, triangles[i].p1 - o);
    vec3 c = sheared(frame, triangles[i].p2 - o);
    // `precise`: a fused multiply-add would round one product and not the
    // other, and the neighbour's edge function would no longer be the exact
    // negative of this one.
    precise float u = c.x * b.y - c.y * b.x;
    precise float v = a.x * c.y - a.y * c.x;
    precise float w = b.x * a.y - b.y * a.x;
    bool inside = (u >= 0.0 && v >= 0.0 && w >= 0.0) || (u <= 0.0 && v <= 0.0 && w <= 0.0);
    float det = u + v + w;
    uv = vec2(v, w) / det;
    return inside && det != 0.0 ? (u * a.z + v * b.z + w * c.z) / det : 0.0;
}

// Entry distance of the ray into a box (the slab test against [0, t_max]),
// or NO_HIT if it misses. A zero direction component gives an infinite
// inverse; the slab test then sorts that axis out (lo - o and hi - o have
// the same sign, or the ray lies inside the slab).
float box_entry(vec3 o, vec3 inv_d, vec3 lo, vec3 hi, float t_max) {
    vec3 t1 = (lo - o) * inv_d;
    vec3 t2 = (hi - o) * inv_d;
    vec3 t_in = min(t1, t2);
    vec3 t_out = max(t1, t2);
    float enter = max(max(t_in.x, t_in.y), max(t_in.z, 0.0));
    float leave = min(min(t_out.x, t_out.y), min(t_out.z, t_max));
    return enter <= leave ? enter : NO_HIT;
}

// The meshes' triangles through the BVH. Nearest-hit (`any_hit` false):
// near child first, the far one stacked with its entry distance and
// skipped when popped beyond the nearest hit. Shadow query (`any_hit`):
// stops at the first hit nearer than best.t. A link is an inner node's
// index, or LEAF_BIT | count - 1 << 26 | the leaf's first triangle.
void hit_meshes(vec3 o, vec3 d, inout Hit best, bool any_hit) {
    uint link = frame.grid.w;  // the root: node 0, or a leaf
    vec3 inv_d = vec3(1.0) / d;
    RayFrame shear = ray_frame(d);
    // Cannot overflow: the host refuses a tree deeper than the stack
    // (rt_layout::BVH_STACK_SIZE), since a dropped node would be a miss.
    uint stack_link[BVH_STACK_SIZE];
    float stack_t[BVH_STACK_SIZE];
    int top = 0;
    bool done = false;
    do {
        if ((link & LEAF_BIT) == 0u) {
            float t_left = box_entry(o, inv_d, nodes[link].left_lo, nodes[link].left_hi, best.t);
            float t_right = box_entry(o, inv_d, nodes[link].right_lo, nodes[link].right_hi, best.t);
            uint left = nodes[link].left;
            uint right = nodes[link].right;
            bool both = t_left != NO_HIT && t_right != NO_HIT;
            bool right_first = t_right < t_left;
            uint next = right_first ? right : left;
            if (both) {
                stack_link[top] = right_first ? left : right;
                stack_t[top] = right_first ? t_left : t_right;
                ++top;
            }
            link = next;
            if (t_left == NO_HIT && t_right == NO_HIT) {
                link = NO_SHAPE;  // pop below
            }
        } else {
            uint first = link & 0x03ffffffu;
            uint end = first + ((link >> 26) & 31u) + 1u;
            for (uint i = first; i < end; ++i) {
                vec2 uv;
                float t = triangle_t(o, shear, i, uv);
                if (any_hit) {
                    if (t > 0.0 && t < best.t) {
                        best = Hit(t, KIND_TRIANGLE | i, uv);
                    }
                } else {
                    consider(t, KIND_TRIANGLE | i, uv, best);
                }
            }
            link = NO_SHAPE;
            if (any_hit && best.shape != NO_SHAPE) {
                return;
            }
        }
        if (link == NO_SHAPE) {
            done = true;
            while (top > 0) {
                --top;
                if (stack_t[top] <= best.t) {
                    link = stack_link[top];
                    done = false;
                    break;
                }
            }
        }
    } while (!done);
}

// Every primitive against the ray: the nearest hit, ties to the lower
// object, then the lower triangle.
Hit nearest(vec3 o, vec3 d) {
    Hit best = Hit(NO_HIT, NO_SHAPE, vec2(0.0));
    for (int i = 0; i < SPHERE_COUNT; ++i) {
        consider(sphere_t(o, d, i), KIND_SPHERE | uint(i), vec2(0.0), best);
    }
    for (int i = 0; i < PLANE_COUNT; ++i) {
        consider(plane_t(o, d, i), KIND_PLANE | uint(i), vec2(0.0), best);
    }
    for (int i = 0; i < BOX_COUNT; ++i) {
        vec2 face;
        float t = box_t(o, d, i, face);
        consider(t, KIND_BOX | uint(i), face, best);
    }
    if (HAS_MESHES) {
        hit_meshes(o, d, best, false);
    }
    return best;
}

// Whether anything is hit at 0 < t < t_max: the shadow-ray query, the twin
// of cpu::intersect::Accel::any. It stops at the first such hit; the BVH
// walk is bounded by t_max.
bool occluded(vec3 o, vec3 d, float t_max) {
    for (int i = 0; i < SPHERE_COUNT; ++i) {
        float t = sphere_t(o, d, i);
        if (t > 0.0 && t < t_max) {
            return true;
        }
    }
    for (int i = 0; i < PLANE_COUNT; ++i) {
        float t = plane_t(o, d, i);
        if (t > 0.0 && t < t_max) {
            return true;
        }
    }
    for (int i = 0; i < BOX_COUNT; ++i) {
        vec2 face;
        float t = box_t(o, d, i, face);
        if (t > 0.0 && t < t_max) {
            return true;
        }
    }
    if (HAS_MESHES) {
        Hit best = Hit(t_max, NO_SHAPE, vec2(0.0));
        hit_meshes(o, d, best, true);
        return best.shape != NO_SHAPE;
    }
    return false;
}

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
    vec3 n = vec3(0.0);
    uint material = 0u;
    if (kind == KIND_SPHERE) {
        n = (p - spheres[index].center_radius.xyz) / spheres[index].center_radius.w;
        material = spheres[index].material_object.x;
    }
    if (kind == KIND_PLANE) {
        n = planes[index].normal.xyz;
        material = planes[index].material_object.x;
    }
    if (kind == KIND_BOX) {
        mat3 rot = mat3(boxes[index].axis_x.xyz, boxes[index].axis_y.xyz, boxes[index].axis_z.xyz);
        vec3 local_normal = vec3(0.0);
        local_normal[int(hit.uv.x)] = hit.uv.y;
        n = rot * local_normal;
        material = boxes[index].material_object.x;
    }
    if (HAS_MESHES && kind == KIND_TRIANGLE) {
        float bu = hit.uv.x;
        float bv = hit.uv.y;
        vec3 shading = (1.0 - bu - bv) * triangle_shading[index].n0 + bu * triangle_shading[index].n1
                       + bv * triangle_shading[index].n2;
        return Surfel(p, unit_or_zero(shading), triangle_shading[index].geometric,
                      triangle_shading[index].material);
    }
    return Surfel(p, n, n, material);
}

// Pushes a secondary ray's origin off the surface, to the side it leaves to,
// by an amount that grows with the hit's distance from the eye.
vec3 offset_origin(vec3 p, vec3 geometric, vec3 dir) {
    vec3 a = abs(p);
    float eps = 1.0e-4 * max(1.0, max(a.x, max(a.y, a.z)));
    float side = dot(geometric, dir) >= 0.0 ? 1.0 : -1.0;
    return p + side * eps * geometric;
}

// Fields are read one by one: naga's SPIR-V reader lacks OpCopyLogical,
// which a whole-struct copy out of a buffer would emit.
Surface surface_of(uint material) {
    vec4 color_ka = materials[material].color_ka;
    vec4 kd_ks_p = materials[material].kd_ks_p_kr;
    return Surface(color_ka.rgb, color_ka.a, kd_ks_p.x, kd_ks_p.y, kd_ks_p.z);
}

vec3 local_shading(Surfel s, Surface m, vec3 d) {
    vec3 intensity = ambient_term(m, frame.ambient_k.rgb);
    vec3 N = s.normal;
    if (N == vec3(0.0)) {
        return intensity;
    }
    for (int j = 0; j < LIGHT_COUNT; ++j) {
        vec3 L;
        float dist;
        float n_dot_l;
        if (!light_faces(j, s.p, N, L, dist, n_dot_l)) {
            continue;
        }
        if (SHADOWS) {
            vec3 o = offset_origin(s.p, s.geometric, L);
            vec3 to_light = lights[j].position.xyz - o;
            float reach = length(to_light);
            count(1);
            // Stop short of the light by the offset epsilon at the light, as
            // the ray starts off the surface: a light lying on a surface would
            // otherwise be hidden by it at random (assets/hard/grazing-light).
            vec3 at = abs(lights[j].position.xyz);
            float light_eps = 1.0e-4 * max(1.0, max(at.x, max(at.y, at.z)));
            if (occluded(o, to_light / reach, reach - light_eps)) {
                continue;
            }
        }
        intensity += light_term(j, N, -d, L, dist, n_dot_l, m, frame.ambient_k.w);
    }
    return intensity;
}

// One sample's ray tree, in the order of docs/raytracing.md: the tree is
// walked depth first with the refracted child before the reflected one. The
// ray in hand goes on to its first child; only a reflected ray whose
// sibling is refracted waits on the stack.
vec3 trace_sample(vec3 dir) {
    Ray waiting[STACK_SIZE];
    int top = 0;
    Ray ray = Ray(vec3(0.0), dir, 1.0, 0);
    count(0);
    vec3 total = vec3(0.0);
    int max_depth = int(frame.image.w);
    float cutoff = frame.forward_cutoff.w;
    bool live = true;
    do {
        deepest = max(deepest, ray.depth);
        Hit hit = nearest(ray.origin, ray.dir);
        live = false;
        if (hit.shape == NO_SHAPE) {
            total += ray.weight * frame.background.rgb;
        } else {
            Surfel s = resolve(ray.origin, ray.dir, hit);
            Surface m = surface_of(s.material);
            total += ray.weight * local_shading(s, m, ray.dir);
            // Specialization constants appear only as whole conditions: naga's
            // SPIR-V reader rejects operators on them (OpSpecConstantOp).
            bool may_branch = false;
            if (HAS_REFLECTION) {
                // No children from a zero normal: no direction to reflect
                // or refract about.
                may_branch = ray.depth < max_depth && s.normal != vec3(0.0);
            }
            if (may_branch) {
                float kr = materials[s.material].kd_ks_p_kr.w;
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
                    float kt = materials[s.material].kt_ior.x;
                    float ior = materials[s.material].kt_ior.y;
                    if (kt > 0.0) {
                        bool entering = dot(N, ray.dir) < 0.0;
                        vec3 n = entering ? N : -N;
                        float eta = entering ? 1.0 / ior : ior;
                        float cos_i = -dot(n, ray.dir);
                        float k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
                        if (k < 0.0) {
                            reflects = true;  // total internal reflection
                            reflect_weight = ray.weight * (kr + kt);
                        } else {
                            refracts = true;
                            refract_dir = normalize(eta * ray.dir + (eta * cos_i - sqrt(k)) * n);
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
                Ray reflected;
                if (reflects) {
                    vec3 r = ray.dir - 2.0 * dot(ray.dir, N) * N;
                    reflected = Ray(offset_origin(s.p, s.geometric, r), r, reflect_weight, ray.depth + 1);
                    count(2);
                }
                if (refracts) {
                    if (reflects) {
                        waiting[top++] = reflected;
                    }
                    ray = Ray(offset_origin(s.p, s.geometric, refract_dir), refract_dir, refract_weight,
                              ray.depth + 1);
                    count(3);
                    live = true;
                } else if (reflects) {
                    ray = reflected;
                    live = true;
                }
            }
        }
        if (HAS_TRANSMISSION && !live && top > 0) {
            ray = waiting[--top];
            live = true;
        }
    } while (live);
    return total;
}

void main() {
    // Workgroups take the 8x8 tiles in the host's order (`tile_order`), a
    // permutation that spreads every contiguous run of workgroups over the
    // whole image: lavapipe hands each thread one contiguous run (in the
    // order x, then y), and in image order one thread would get the sky and
    // the other the scene.
    uint tile = tile_order[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x];
    uint tiles_across = frame.grid.z;
    uint lane = gl_LocalInvocationIndex;
    uint block = lane >> 3;
    uvec2 pixel = uvec2((tile % tiles_across) * 8u + (block & 1u) * 4u + (lane & 3u),
                        (tile / tiles_across) * 8u + (block >> 1) * 2u + ((lane >> 2) & 1u));
    uint width = frame.image.x;
    uint height = frame.image.y;
    if (pixel.x >= width || pixel.y >= height) {
        return;
    }
    for (int k = 0; k < 5; ++k) {
        local_counts[k] = 0u;
    }
    uint samples = frame.image.z;
    uint kx = frame.grid.x;
    uint ky = frame.grid.y;
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < samples; ++i) {
        float sx = (float(i % kx) + 0.5) / float(kx);
        float sy = (float(i / kx) + 0.5) / float(ky);
        float ndc_x = 2.0 * (float(pixel.x) + sx) / float(width) - 1.0;
        float ndc_y = 2.0 * (float(pixel.y) + sy) / float(height) - 1.0;
        float focal = frame.right_focal.w;
        vec3 dir = frame.forward_cutoff.xyz + frame.right_focal.xyz * (ndc_x * frame.up_aspect.w / focal)
                   - frame.up_aspect.xyz * (ndc_y / focal);
        sum += trace_sample(normalize(dir));
    }
    pixels[pixel.y * width + pixel.x] = vec4(sum / float(samples), 1.0);
    if (COUNT_RAYS) {
        for (int k = 0; k < 5; ++k) {
            if (local_counts[k] > 0u) {
                atomicAdd(counters[k], local_counts[k]);
            }
        }
        atomicMax(counters[5], uint(deepest));
    }
}
