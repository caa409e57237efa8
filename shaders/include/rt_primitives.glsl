// The ray tracer's intersection tests, each a distance along the ray or 0
// for none: spheres (huge ones in their anchored form), planes, boxes and
// triangles; and the tests of a ray's line against a bounding sphere that
// let a packet skip that work.
#ifndef RT_PRIMITIVES_GLSL
#define RT_PRIMITIVES_GLSL

#include "rt_interface.glsl"
#include "rt_ray.glsl"
#include "rt_packet.glsl"
#include "rt_objects.glsl"

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
// quads from TRI_X (tests/cpu/shader_interface.rs holds TRI_Y and TRI_Z to
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

#endif
