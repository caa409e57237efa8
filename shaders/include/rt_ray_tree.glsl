// The ray tracer's recursion: reflection and refraction, one sample's ray
// tree walked with a stack of the rays that wait; compiled with PATHS,
// diffuse bounces too (docs/lighting-model.md, "Secondary illumination").

#ifndef RT_RAY_TREE_GLSL
#define RT_RAY_TREE_GLSL

#include "kernel_sizes.glsl"
#include "rt_interface.glsl"
#include "rt_ray.glsl"
#include "rt_packet.glsl"
#include "rt_objects.glsl"
#include "rt_search.glsl"
#include "rt_surface.glsl"
#include "rt_shading.glsl"
#include "rt_children.glsl"
#ifdef PATHS
#include "random_streams.glsl"
#include "rt_bounce.glsl"

// The diffuse albedo kd C of the hit `shade_hit` shaded last, after
// vertex colours, patterns and images: a bounce's weight.
vec3 hit_albedo = vec3(0.0);
// The sample being traced, whose numbers its bounces draw: set by the
// kernel (`start_pixel_sample`) before it calls trace_sample.
Sampler sample_sampler;
// Bounces wait on the stack, as refracted rays' siblings do.
#define RAYS_WAIT true
#else
#define RAYS_WAIT HAS_TRANSMISSION
#endif

// The local model's light at a hit, shadow rays included, and the surface
// and material the hit's children need. Call in uniform control flow
// (shadow rays walk the BVH as packets); a lane whose ray `hits` nothing
// keeps `s` as it was, casts no shadow rays and gets the ambient term.
vec3 shade_hit(Ray ray, Hit hit, bool hits, vec2 cone, inout Surfel s, out MaterialRecord material) {
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
#ifdef PATHS
    hit_albedo = surface.kd * surface.color;
    // After a diffuse bounce the Phong lobe counts no more.
    if (ray.bounces > 0) {
        surface.ks = 0.0;
    }
#endif
    return local_shading(s, surface, ray.origin, ray.dir, hits);
}

// The children's cones start as wide as this one at the hit;
// a mirror sphere spreads its reflection by 2 w / r more
// (its curvature), flat surfaces and refraction do not.
void child_cones(vec2 cone, Hit hit, out vec2 refracted_cone, out vec2 reflected_cone) {
    refracted_cone = vec2(0.0);
    reflected_cone = vec2(0.0);
    if (TEXTURES) {
        float width = cone.x + cone.y * hit.t;
        float curvature = 0.0;
        if ((hit.shape & KIND_MASK) == KIND_SPHERE) {
            curvature = 2.0 * width / sphere_geometry(int(hit.shape & ~KIND_MASK)).radius;
        }
        refracted_cone = vec2(width, cone.y);
        reflected_cone = vec2(width, cone.y + curvature);
    }
}

// A child of `ray` at its hit `s`: leaving along `dir`, from an origin off
// the surface, one level deeper.
Ray child_ray(Ray ray, Surfel s, vec3 dir, WEIGHT weight) {
#ifdef PATHS
    // A mirror's or glass's child keeps its path's bounces.
    return Ray(offset_origin(s.p, ray.origin, s.geometric, dir), dir, weight, ray.depth + 1, ray.bounces);
#else
    return Ray(offset_origin(s.p, ray.origin, s.geometric, dir), dir, weight, ray.depth + 1);
#endif
}

#ifdef PATHS
// The diffuse bounce of `ray`'s hit `s` (at distance `t`, albedo
// `hit_albedo`) and its cone, drawn with `sample_sampler`'s numbers: false where
// the hit takes none (the depth or the bounce limit reached, a zero
// normal, a black surface), where Russian roulette ends the path, or where
// the direction leaves below the surface's geometric side
// (src/cpu/raytrace/tracer.rs, `bounce`).
bool bounce_of(Ray ray, Surfel s, float t, vec2 cone, out Ray bounced, out vec2 bounce_cone) {
    bounce_cone = vec2(0.0);
    if (TEXTURES) {
        // As a refracted ray's: as wide as this one at the hit.
        bounce_cone = vec2(cone.x + cone.y * t, cone.y);
    }
    bounced = ray;
    bool kept = ray.depth < int(frame.image.w) && s.normal != vec3(0.0) && ray.bounces < int(frame.leaf_bases.w) &&
                hit_albedo != vec3(0.0);
    // No hash, no direction for a hit that takes no bounce: every hit of a
    // path's last bounce, and every black surface (the CPU twin tests first
    // too). Nothing here shuffles, so a lane may leave early.
    if (!kept) {
        return false;
    }
    vec3 u = bounce_numbers(sample_sampler, ray.depth);
    vec3 weight = ray.weight * hit_albedo;
    if (ray.bounces >= ROULETTE_AFTER) {
        float q = min(LARGEST(weight), 1.0);
        kept = u.z < q;
        if (kept) {
            weight /= q;
        } else {
            count(4);
        }
    }
    vec3 facing = dot(s.geometric, ray.dir) > 0.0 ? -s.normal : s.normal;
    vec3 dir = cosine_direction(facing, u.x, u.y);
    kept = kept && dot(s.geometric, dir) * dot(s.geometric, ray.dir) < 0.0;
    bounced = Ray(offset_origin(s.p, ray.origin, s.geometric, dir), dir, weight, ray.depth + 1, ray.bounces + 1);
    if (kept) {
        count(2);
    }
    return kept;
}
#endif

// Whether the packet goes on: some lane has a ray (`live`). Without
// refraction no ray waits, so where nothing was hit the packet is done,
// and a miss costs one vote, not two. Without a BVH, no vote (see
// trace_sample).
bool packet_goes_on_with(bool live, bool packet_hits) {
    bool goes_on;
    if (HAS_BVH) {
        if (RAYS_WAIT) {
            goes_on = packet_any(live);
        } else {
            goes_on = packet_hits && packet_any(live);
        }
    } else {
        goes_on = live;
    }
    return goes_on;
}

// One sample's ray tree, in the order of docs/raytracing.md: the tree is
// walked depth first with the refracted child before the reflected one. The
// ray in hand goes on to its first child; only a reflected ray whose
// sibling is refracted waits on the stack. The subgroup goes on while any
// lane has a ray (the walks are packets); `live` says whether this one has.
//
// Each ray's cone (an image's level of detail) is its width at the origin
// and its growth per unit of distance, kept beside the rays and touched
// only with TEXTURES, so that a scene without images carries none of it
// (its pipeline compiled as fast as before them). A primary cone widens by
// a pixel's height per unit of distance (level_of_detail::pixel_spread).
//
// Shading walks shadow rays as packets: the whole subgroup comes to it, or
// none of it (where every ray left the scene). With no BVH nothing there
// shuffles, so each lane goes its own way and the driver's masks do what
// the votes did, for less (a vote is three shuffles; the four spheres took
// 0.9x the time without).
//
// The first search goes without a vote: a packet with no pixel on the
// image is rare (the image's edges), and its lanes find nothing. No
// children from a zero normal: no direction to reflect or refract about.
// (Specialization constants appear only as whole conditions: naga's SPIR-V
// reader rejects operators on them, OpSpecConstantOp.)
//
// With PATHS a hit's diffuse bounce waits on the stack below its mirror
// and glass children, so it is traced after them, as on the CPU; its
// numbers are `sample_sampler`'s. The background lights nothing there:
// only eye rays (no bounce yet) see it.
// A ray's nearest hit; with PAIRED the eye ray's is `first`, found with
// another pixel's by nearest_pair (rt_paired.glsl). `eye_ray` is the same
// in every lane, so the search stays in uniform control flow.
#ifdef PAIRED
#define EYE_HIT_PARAMETER , Hit first
#define EYE_HIT_ARGUMENT , first
Hit search_from(Ray ray, bool live, bool eye_ray, Hit first) {
    if (eye_ray) {
        return first;
    }
    return nearest(ray.origin, ray.dir, live);
}
#else
#define EYE_HIT_PARAMETER
#define EYE_HIT_ARGUMENT
Hit search_from(Ray ray, bool live, bool eye_ray) {
    return nearest(ray.origin, ray.dir, live);
}
#endif

vec3 trace_sample(vec3 dir, bool live EYE_HIT_PARAMETER) {
    Ray waiting[STACK_SIZE];
    vec2 waiting_cones[STACK_SIZE];
    int top = 0;
#ifdef PATHS
    Ray ray = Ray(vec3(0.0), dir, WEIGHT(1.0), 0, 0);
#else
    Ray ray = Ray(vec3(0.0), dir, WEIGHT(1.0), 0);
#endif
    vec2 cone = vec2(0.0);
    if (TEXTURES) {
        cone.y = 2.0 / (frame.right_focal.w * float(frame.image.y));
    }
    if (live) {
        count(0);
    }
    vec3 total = vec3(0.0);
    int max_depth = int(frame.image.w);
    float cutoff = frame.forward_cutoff.w;
    bool packet_goes_on = true, eye_ray = true;
    while (packet_goes_on) {
        if (live) {
            deepest = max(deepest, ray.depth);
        }
        Hit hit = search_from(ray, live, eye_ray EYE_HIT_ARGUMENT);
        eye_ray = false;
        bool hits = live && hit.shape != NO_SHAPE;
        if (live && !hits) {
#ifdef PATHS
            if (ray.bounces == 0)
#endif
                total += ray.weight * frame.background.rgb;
        }
        Surfel s = Surfel(vec3(0.0), vec3(0.0), vec3(0.0), 0u);
        MaterialRecord material = MaterialRecord(vec4(0.0), vec4(0.0), vec2(0.0));
        vec3 local = vec3(0.0);
        bool packet_hits = HAS_BVH ? packet_any(hits) : hits;
        if (packet_hits) {
            local = shade_hit(ray, hit, hits, cone, s, material);
        }
        live = false;
        if (hits) {
            total += ray.weight * local;
            bool may_branch = false;
            if (HAS_REFLECTION) {
                may_branch = ray.depth < max_depth && s.normal != vec3(0.0);
            }
#ifdef PATHS
            Ray bounced;
            vec2 bounce_cone;
            if (bounce_of(ray, s, hit.t, cone, bounced, bounce_cone)) {
                if (TEXTURES) {
                    waiting_cones[top] = bounce_cone;
                }
                waiting[top++] = bounced;
            }
#endif
            if (may_branch) {
                Children c = children_of(ray, s.normal, material, cutoff);
                vec2 refracted_cone, reflected_cone;
                child_cones(cone, hit, refracted_cone, reflected_cone);
                Ray reflected;
                if (c.reflects) {
                    vec3 r = ray.dir - 2.0 * dot(ray.dir, s.normal) * s.normal;
                    reflected = child_ray(ray, s, r, c.reflect_weight);
                    count(2);
                }
                if (c.refracts) {
                    if (c.reflects) {
                        if (TEXTURES) {
                            waiting_cones[top] = reflected_cone;
                        }
                        waiting[top++] = reflected;
                    }
                    ray = child_ray(ray, s, c.refract_dir, c.refract_weight);
                    if (TEXTURES) {
                        cone = refracted_cone;
                    }
                    count(3);
                    live = true;
                } else if (c.reflects) {
                    ray = reflected;
                    if (TEXTURES) {
                        cone = reflected_cone;
                    }
                    live = true;
                }
            }
        }
        if (RAYS_WAIT && !live && top > 0) {
            ray = waiting[--top];
            if (TEXTURES) {
                cone = waiting_cones[top];
            }
            live = true;
        }
        packet_goes_on = packet_goes_on_with(live, packet_hits);
    }
    return total;
}

#endif
