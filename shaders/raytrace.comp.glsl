#version 460
#extension GL_GOOGLE_include_directive : require
// Backward (Whitted) ray tracing, one invocation per pixel, exactly as
// docs/raytracing.md specifies (its CPU twin is src/cpu/raytrace.rs):
// stratified samples, nearest hits with the object-order tie rule, shadow
// rays, reflection and refraction with total internal reflection, and an
// explicit stack in place of recursion.

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "rt_interface.glsl"
#include "lighting.glsl"

// Depth is at most 64 (checked on the host); the stack needs depth + 1.
const int STACK_SIZE = 65;
const int BVH_STACK_SIZE = 64;
const float NO_HIT = 3.0e38;

struct Hit {
    float t;
    vec3 normal;     // shading normal (zero for a degenerate interpolation)
    vec3 geometric;  // unit geometric normal, for offsets
    uint material;
    uint object;
    uint primitive;  // the triangle's index for meshes, else 0
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

// Whether a hit at t on `object` (triangle `primitive` of a mesh) beats the
// nearest so far: exact ties go to the lower object, then the lower triangle.
bool nearer(float t, uint object, uint primitive, Hit best) {
    if (t != best.t) {
        return t < best.t;
    }
    return object < best.object || (object == best.object && primitive < best.primitive);
}

void hit_sphere(vec3 o, vec3 d, uint index, inout Hit best) {
    vec3 c = spheres[index].center_radius.xyz;
    float r = spheres[index].center_radius.w;
    vec3 f = o - c;
    float b = -dot(f, d);
    vec3 l = f + b * d;
    float disc = r * r - dot(l, l);
    if (disc < 0.0) {
        return;
    }
    float q = b + (b >= 0.0 ? 1.0 : -1.0) * sqrt(disc);
    if (q == 0.0) {
        return;
    }
    float t0 = (dot(f, f) - r * r) / q;
    float t1 = q;
    float t = min(t0, t1) > 0.0 ? min(t0, t1) : max(t0, t1);
    uint object = spheres[index].material_object.y;
    if (t > 0.0 && nearer(t, object, 0u, best)) {
        vec3 n = (o + t * d - c) / r;
        best = Hit(t, n, n, spheres[index].material_object.x, object, 0u);
    }
}

void hit_plane(vec3 o, vec3 d, uint index, inout Hit best) {
    vec3 c = planes[index].center_half.xyz;
    vec3 n = planes[index].normal.xyz;
    float denom = dot(d, n);
    if (denom == 0.0) {
        return;
    }
    float t = dot(c - o, n) / denom;
    uint object = planes[index].material_object.y;
    if (!(t > 0.0) || !nearer(t, object, 0u, best)) {
        return;
    }
    vec3 rel = o + t * d - c;
    float h = planes[index].center_half.w;
    if (abs(dot(rel, planes[index].u.xyz)) <= h && abs(dot(rel, planes[index].v.xyz)) <= h) {
        best = Hit(t, n, n, planes[index].material_object.x, object, 0u);
    }
}

void hit_box(vec3 o, vec3 d, uint index, inout Hit best) {
    mat3 rot = mat3(boxes[index].axis_x.xyz, boxes[index].axis_y.xyz, boxes[index].axis_z.xyz);
    vec3 h = boxes[index].half_extents.xyz;
    vec3 lo = transpose(rot) * (o - boxes[index].center.xyz);
    vec3 ld = transpose(rot) * d;
    float t_near = -NO_HIT;
    float t_far = NO_HIT;
    int near_axis = 0;
    int far_axis = 0;
    for (int a = 0; a < 3; ++a) {
        if (ld[a] == 0.0) {
            if (abs(lo[a]) > h[a]) {
                return;
            }
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
    if (t_far < max(t_near, 0.0)) {
        return;
    }
    float t = t_near > 0.0 ? t_near : t_far;
    int axis = t_near > 0.0 ? near_axis : far_axis;
    uint object = boxes[index].material_object.y;
    if (!(t > 0.0) || !nearer(t, object, 0u, best)) {
        return;
    }
    vec3 local_normal = vec3(0.0);
    local_normal[axis] = (lo[axis] + t * ld[axis]) >= 0.0 ? 1.0 : -1.0;
    vec3 n = rot * local_normal;
    best = Hit(t, n, n, boxes[index].material_object.x, object, 0u);
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

void hit_triangle(vec3 o, RayFrame frame, uint index, inout Hit best) {
    vec3 p0 = triangles[index].p0.xyz;
    vec3 p1 = triangles[index].p1.xyz;
    vec3 p2 = triangles[index].p2.xyz;
    vec3 a = sheared(frame, p0 - o);
    vec3 b = sheared(frame, p1 - o);
    vec3 c = sheared(frame, p2 - o);
    // `precise`: a fused multiply-add would round one product and not the
    // other, and the neighbour's edge function would no longer be the exact
    // negative of this one.
    precise float u = c.x * b.y - c.y * b.x;
    precise float v = a.x * c.y - a.y * c.x;
    precise float w = b.x * a.y - b.y * a.x;
    bool inside = (u >= 0.0 && v >= 0.0 && w >= 0.0) || (u <= 0.0 && v <= 0.0 && w <= 0.0);
    float det = u + v + w;
    if (!inside || det == 0.0) {
        return;
    }
    float t = (u * a.z + v * b.z + w * c.z) / det;
    uint object = triangles[index].material_object.y;
    if (!(t > 0.0) || !nearer(t, object, index, best)) {
        return;
    }
    float bu = v / det;
    float bv = w / det;
    vec3 n = unit_or_zero((1.0 - bu - bv) * triangles[index].n0.xyz + bu * triangles[index].n1.xyz
                          + bv * triangles[index].n2.xyz);
    best = Hit(t, n, unit_or_zero(cross(p1 - p0, p2 - p0)), triangles[index].material_object.x, object, index);
}

// Slab test of a BVH node against [0, t_max].
bool hits_node(vec3 o, vec3 inv_d, uint node, float t_max) {
    vec3 t1 = (nodes[node].lo - o) * inv_d;
    vec3 t2 = (nodes[node].hi - o) * inv_d;
    vec3 t_in = min(t1, t2);
    vec3 t_out = max(t1, t2);
    float enter = max(max(t_in.x, t_in.y), max(t_in.z, 0.0));
    float leave = min(min(t_out.x, t_out.y), min(t_out.z, t_max));
    return enter <= leave;
}

// `stop_below`: return as soon as a hit nearer than this is found (a
// shadow ray's any-hit query; negative for the nearest hit).
void hit_meshes(vec3 o, vec3 d, inout Hit best, float stop_below) {
    // A zero direction component gives an infinite inverse; the slab test
    // then sorts that axis out (lo - o and hi - o have the same sign or
    // the ray lies inside the slab).
    vec3 inv_d = vec3(1.0) / d;
    RayFrame frame = ray_frame(d);
    // Cannot overflow: the host refuses a tree deeper than the stack
    // (rt_layout::BVH_STACK_SIZE), since a dropped node would be a miss.
    uint stack[BVH_STACK_SIZE];
    int top = 0;
    stack[top++] = 0u;
    while (top > 0) {
        uint node = stack[--top];
        if (!hits_node(o, inv_d, node, best.t)) {
            continue;
        }
        uint count = nodes[node].prim_count;
        uint first = nodes[node].first;
        if (count > 0u) {
            for (uint k = 0u; k < count; ++k) {
                hit_triangle(o, frame, primitive_indices[first + k], best);
            }
            if (best.t < stop_below) {
                return;
            }
        } else if (top + 2 <= BVH_STACK_SIZE) {
            stack[top++] = first + 1u;
            stack[top++] = first;
        }
    }
}

// Every primitive against the ray, keeping the nearest hit in `best`;
// returns early once `best.t < stop_below` (see hit_meshes).
void hit_all(vec3 o, vec3 d, inout Hit best, float stop_below) {
    if (HAS_SPHERES) {
        for (uint i = 0u; i < frame.counts.x; ++i) {
            hit_sphere(o, d, i, best);
        }
        if (best.t < stop_below) {
            return;
        }
    }
    if (HAS_PLANES) {
        for (uint i = 0u; i < frame.counts.y; ++i) {
            hit_plane(o, d, i, best);
        }
        if (best.t < stop_below) {
            return;
        }
    }
    if (HAS_BOXES) {
        for (uint i = 0u; i < frame.counts.z; ++i) {
            hit_box(o, d, i, best);
        }
        if (best.t < stop_below) {
            return;
        }
    }
    if (HAS_MESHES) {
        hit_meshes(o, d, best, stop_below);
    }
}

Hit nearest(vec3 o, vec3 d) {
    Hit best = Hit(NO_HIT, vec3(0.0), vec3(0.0), 0u, 0xffffffffu, 0xffffffffu);
    hit_all(o, d, best, -1.0);
    return best;
}

// Whether anything is hit at 0 < t < t_max: the shadow-ray query, the twin
// of cpu::intersect::Accel::any. It starts from a "hit" at t_max with the
// lowest object index, which only a strictly nearer hit replaces
// (`nearer`), and stops at the first one; the BVH walk is bounded by t_max.
bool occluded(vec3 o, vec3 d, float t_max) {
    Hit best = Hit(t_max, vec3(0.0), vec3(0.0), 0u, 0u, 0u);
    hit_all(o, d, best, t_max);
    return best.t < t_max;
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

vec3 local_shading(vec3 p, Hit hit, vec3 d) {
    Surface m = surface_of(hit.material);
    vec3 intensity = ambient_term(m, frame.ambient_k.rgb);
    vec3 N = hit.normal;
    if (N == vec3(0.0)) {
        return intensity;
    }
    for (int j = 0; j < LIGHT_COUNT; ++j) {
        vec3 L;
        float dist;
        float n_dot_l;
        if (!light_faces(j, p, N, L, dist, n_dot_l)) {
            continue;
        }
        if (SHADOWS) {
            vec3 o = offset_origin(p, hit.geometric, L);
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

vec3 trace_sample(vec3 dir) {
    Ray stack[STACK_SIZE];
    int top = 0;
    stack[top++] = Ray(vec3(0.0), dir, 1.0, 0);
    count(0);
    vec3 total = vec3(0.0);
    int max_depth = int(frame.image.w);
    float cutoff = frame.forward_cutoff.w;
    while (top > 0) {
        Ray ray = stack[--top];
        deepest = max(deepest, ray.depth);
        Hit hit = nearest(ray.origin, ray.dir);
        if (hit.t == NO_HIT) {
            total += ray.weight * frame.background.rgb;
            continue;
        }
        vec3 p = ray.origin + hit.t * ray.dir;
        total += ray.weight * local_shading(p, hit, ray.dir);
        // Specialization constants appear only as whole conditions: naga's
        // SPIR-V reader rejects operators on them (OpSpecConstantOp).
        bool may_branch = false;
        if (HAS_REFLECTION) {
            may_branch = ray.depth < max_depth;
        }
        if (!may_branch) {
            continue;
        }
        float kr = materials[hit.material].kd_ks_p_kr.w;
        float kt = materials[hit.material].kt_ior.x;
        float ior = materials[hit.material].kt_ior.y;
        vec3 N = hit.normal;
        if (N == vec3(0.0)) {
            continue;  // no direction to reflect or refract about
        }
        // Decided by kr and total internal reflection, not by the weight, as
        // on the CPU: a weight that underflows in f32 is still a child (pruned).
        bool reflects = kr > 0.0;
        float reflect_weight = ray.weight * kr;
        bool refracts = false;
        vec3 refract_dir = vec3(0.0);
        bool transmits = false;
        if (HAS_TRANSMISSION) {
            transmits = kt > 0.0;
        }
        if (transmits) {
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
            }
        }
        if (reflects) {
            if (reflect_weight < cutoff) {
                count(4);
            } else {
                vec3 r = ray.dir - 2.0 * dot(ray.dir, N) * N;
                stack[top++] = Ray(offset_origin(p, hit.geometric, r), r, reflect_weight, ray.depth + 1);
                count(2);
            }
        }
        if (refracts) {
            float w = ray.weight * kt;
            if (w < cutoff) {
                count(4);
            } else {
                stack[top++] = Ray(offset_origin(p, hit.geometric, refract_dir), refract_dir, w, ray.depth + 1);
                count(3);
            }
        }
    }
    return total;
}

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
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
