// One photon's flight from a light and its splats toward the eye
// (forward.comp.glsl): the twin of src/cpu/forward/photon.rs, in the order
// of docs/lighting-model.md, "Forward: photons from the lights". Shared
// with the photon map (rt_caustics.glsl). For the kernels compiled with
// FORWARD, whose interface has the film.
#ifndef RT_PHOTON_GLSL
#define RT_PHOTON_GLSL

#include "rt_interface.glsl"
#include "lighting.glsl"
#include "film_fixed.glsl"
#include "random_streams.glsl"
#include "rt_ray.glsl"
#include "rt_packet.glsl"
#include "rt_objects.glsl"
#include "rt_search.glsl"
#include "rt_surface.glsl"
#include "rt_shading.glsl"
#include "rt_bounce.glsl"
#include "rt_children.glsl"

// What this invocation's photons did (flushed once, at the end).
uint64_t counted_photons[4];

// A photon on its way: as `Flight` on the CPU.
struct Flight {
    vec3 origin;
    vec3 dir;
    // Without the falloff until the path's first surface that is not a
    // mirror or glass has been left by a diffuse bounce; with it after.
    vec3 flux;
    // The path's length from the light so far, while the falloff waits.
    float travelled;
    bool falloff_applied;
    // Diffuse surfaces met so far.
    int diffuse_vertices;
};

// Photon i's four numbers at `level` (0: the light and the direction; n:
// the event at its n-th surface; `random_streams::Sampler::photon`).
vec4 photon_numbers(uint i, int level) {
    return sampler_at_level(start_photon(i), level);
}

// The light `u` picks and its chance: each light's running share of the
// power is in its record's w (a multiple of 2^-24, the last 1), so the
// pick is exact, as on the host (cpu::forward::LightChoice).
int light_of(float u, out float chance) {
    int picked = -1;
    float below = 0.0;
    chance = 0.0;
    for (int j = 0; j < LIGHT_COUNT; ++j) {
        float share = lights[j].position.w;
        if (picked < 0 && u < share) {
            picked = j;
            chance = share - below;
        }
        below = share;
    }
    // u < 1, and the last light's share is 1: never taken.
    return max(picked, 0);
}

// The falloff's factor on a photon's flux at path length d from its
// light: d^2 F(d), so that its density on a surface falls off as the
// scene says (1 with inverse-square falloff).
float falloff_factor(float d) {
    // (Specialization constants only as whole conditions: naga's SPIR-V
    // reader rejects operators on them.)
    if (USE_ATTENUATION) {
        return INVERSE_SQUARE ? 1.0 : d * d / (d + frame.ambient_k.w);
    }
    return d * d;
}

// Where a splat lands and what it adds, or `lands` false.
struct Splat {
    bool lands;
    uint pixel;
    vec3 value;
    // The shadow ray toward the eye.
    vec3 origin;
    vec3 dir;
    float reach;
};

// The pixel the eye sees camera-relative `p` in (at distance `distance`)
// and the cosine between the ray to it and the view axis; false behind
// the eye or off the image. The inverse of the eye rays' directions.
bool pixel_of(vec3 p, float distance, out uint pixel, out float cos_c) {
    vec3 dir = p / distance;
    cos_c = dot(dir, frame.forward_cutoff.xyz);
    pixel = 0u;
    if (!(cos_c > 0.0)) {
        return false;
    }
    float focal = frame.right_focal.w;
    float ndc_x = focal / frame.up_aspect.w * dot(dir, frame.right_focal.xyz) / cos_c;
    float ndc_y = -focal * dot(dir, frame.up_aspect.xyz) / cos_c;
    vec2 size = vec2(frame.image.xy);
    vec2 xy = (vec2(ndc_x, ndc_y) + 1.0) * 0.5 * size;
    if (!(xy.x >= 0.0 && xy.x < size.x && xy.y >= 0.0 && xy.y < size.y)) {
        return false;
    }
    pixel = uint(xy.y) * frame.image.x + uint(xy.x);
    return true;
}

// The splat of a photon of flux `arriving` along `f.dir` at `s`:
// `flux f cos_x / (r^2 cos_c^3 A)`, f = kd C (N.L / Ng.L) (+ ks S / Ng.L on
// the photon's first surface), where the eye sees the side it lit and the
// point is on the image; the shadow ray is the caller's.
Splat splat_at(Flight f, Surfel s, Surface m, vec3 albedo, vec3 arriving, bool first_surface) {
    Splat out_splat = Splat(false, 0u, vec3(0.0), vec3(0.0), vec3(0.0, 0.0, 1.0), -1.0);
    vec3 ng = s.geometric;
    float distance = length(s.p);
    vec3 v = -s.p / distance;
    vec3 l = -f.dir;
    if (dot(ng, v) * dot(ng, l) <= 0.0) {
        return out_splat;
    }
    vec3 n = dot(ng, f.dir) > 0.0 ? -s.normal : s.normal;
    float n_dot_l = dot(n, l);
    float cos_c;
    if (n_dot_l <= 0.0 || !pixel_of(s.p, distance, out_splat.pixel, cos_c)) {
        return out_splat;
    }
    vec3 o = offset_origin(s.p, f.origin, ng, v);
    float to_eye = length(o);
    out_splat.origin = o;
    out_splat.dir = -o / to_eye;
    out_splat.reach = to_eye - offset_epsilon(vec3(0.0), o);
    float ng_dot_l = abs(dot(ng, l));
    vec3 brdf = albedo * (n_dot_l / ng_dot_l);
    if (USE_SPECULAR) {
        if (first_surface && m.ks > 0.0) {
            vec3 reflected = 2.0 * n_dot_l * n - l;
            float r_dot_v = max(dot(reflected, v), 0.0);
            float lobe = m.p == 0.0 ? 1.0 : (r_dot_v > 0.0 ? pow(r_dot_v, m.p) : 0.0);
            brdf += vec3(m.ks * lobe / ng_dot_l);
        }
    }
    float cos_x = abs(dot(ng, v));
    float pixel_side = 2.0 / (frame.right_focal.w * float(frame.image.y));
    out_splat.value = arriving * brdf * cos_x / (distance * distance * cos_c * cos_c * cos_c * pixel_side * pixel_side);
    out_splat.lands = true;
    return out_splat;
}

// Adds a splat to its pixel's fixed-point sums, rounded to nearest; one
// that is not finite adds nothing.
void add_to_film(uint pixel, vec3 value) {
    for (int c = 0; c < 3; ++c) {
        float scaled = value[c] * FILM_ONE;
        if (scaled >= 0.5 && scaled <= FILM_MAX) {
            atomicAdd(film[3u * pixel + uint(c)], uint64_t(scaled + 0.5));
        }
    }
}

// Sends the photon on from its hit by one event picked with u.x in
// proportion to mean(kd C) (where `diffuse_allowed` and while diffuse
// bounces are left), kr and kt (total internal reflection giving kt to the
// reflection), scaled down together where they add to more than 1;
// whether it goes on (not absorbed, nor sent below the surface).
bool go_on(inout Flight f, Surfel s, MaterialRecord material, vec3 albedo, vec3 arriving, vec4 u,
           bool diffuse_allowed) {
    vec3 d = f.dir;
    Children c = children_of(Ray(f.origin, d, 1.0, 0), s.normal, material, 0.0);
    float p_diffuse = 0.0;
    if (diffuse_allowed && f.diffuse_vertices <= int(frame.leaf_bases.w) && albedo != vec3(0.0)) {
        p_diffuse = (albedo.x + albedo.y + albedo.z) / 3.0;
    }
    float p_reflect = c.reflects ? c.reflect_weight : 0.0;
    float p_refract = c.refracts ? c.refract_weight : 0.0;
    float scale = max(p_diffuse + p_reflect + p_refract, 1.0);
    float pick = u.x * scale;
    vec3 ng = s.geometric;
    vec3 dir;
    if (pick < p_diffuse) {
        dir = cosine_direction(dot(ng, d) > 0.0 ? -s.normal : s.normal, u.y, u.z);
        // Back out on the side the photon came from, or nothing.
        if (dot(ng, dir) * dot(ng, d) >= 0.0) {
            return false;
        }
        f.flux = arriving * albedo * (scale / p_diffuse);
        f.falloff_applied = true;
    } else if (pick < p_diffuse + p_reflect || pick < p_diffuse + p_reflect + p_refract) {
        dir = pick < p_diffuse + p_reflect ? d - 2.0 * dot(d, s.normal) * s.normal : c.refract_dir;
        f.flux *= scale;
        if (!f.falloff_applied) {
            f.travelled += length(s.p - f.origin);
        }
    } else {
        return false;
    }
    f.origin = offset_origin(s.p, f.origin, ng, dir);
    f.dir = dir;
    return true;
}

// Photon i of `total` as it leaves its light: the light its power picks,
// a direction drawn uniformly over the sphere, and its share of the
// light's power (cpu::forward::Flight::emit).
Flight emit_photon(uint i, uint total) {
    vec4 u = photon_numbers(i, 0);
    float chance;
    int j = light_of(u.x, chance);
    float z = 1.0 - 2.0 * u.y;
    float r = sqrt(max(1.0 - z * z, 0.0));
    float phi = 6.283185307179586 * u.z;
    return Flight(lights[j].position.xyz, vec3(r * cos(phi), r * sin(phi), z),
                  12.566370614359172 * lights[j].intensity.rgb / (float(total) * chance), 0.0, false, 0);
}

// Photon i of `total`'s flight, if `live`. Call in uniform control flow
// (its searches walk the BVH as packets): a lane with no photon takes part
// with none.
void trace_photon(uint i, uint total, bool live) {
    Flight f = emit_photon(i, total);
    if (live) {
        counted_photons[0] += 1ul;
    }
    bool seen = false;
    int depth = int(frame.image.w);
    for (int level = 0;; ++level) {
        Hit hit = nearest(f.origin, f.dir, live);
        bool hits = live && hit.shape != NO_SHAPE;
        Surfel s = Surfel(vec3(0.0), vec3(0.0), vec3(0.0), 0u);
        MaterialRecord material = MaterialRecord(vec4(0.0), vec4(0.0), vec2(0.0));
        Surface m = Surface(vec3(0.0), 0.0, 0.0, 0.0, 0.0);
        vec3 albedo = vec3(0.0);
        vec3 arriving = f.flux;
        bool first_surface = f.diffuse_vertices == 0;
        Splat splat = Splat(false, 0u, vec3(0.0), vec3(0.0), vec3(0.0, 0.0, 1.0), -1.0);
        if (hits) {
            counted_photons[3] += 1ul;
            s = resolve(f.origin, f.dir, hit);
            material = material_at(s.material);
            m = surface_of(material);
            vec3 tint = vec3(1.0);
            if (VERTEX_COLORS) {
                tint *= hit_tint(hit);
            }
            if (PATTERNS) {
                tint *= hit_pattern(hit, s, f.dir, 0.0);
            }
            albedo = m.kd * m.color * tint;
            if (!f.falloff_applied) {
                arriving = f.flux * falloff_factor(f.travelled + hit.t);
            }
            bool shows = albedo != vec3(0.0) || (first_surface && m.ks > 0.0);
            if (shows && s.normal != vec3(0.0)) {
                splat = splat_at(f, s, m, albedo, arriving, first_surface);
            }
        }
        // Every lane comes here: the shadow rays walk as a packet.
        bool blocked = occluded(splat.origin, splat.dir, splat.lands ? splat.reach : -1.0);
        if (splat.lands && !blocked) {
            add_to_film(splat.pixel, splat.value);
            counted_photons[1] += 1ul;
            seen = true;
        }
        if (albedo != vec3(0.0)) {
            f.diffuse_vertices += 1;
        }
        live = hits && level < depth && s.normal != vec3(0.0) &&
               go_on(f, s, material, albedo, arriving, photon_numbers(i, level + 1), true);
        if (!(HAS_BVH ? packet_any(live) : live)) {
            break;
        }
    }
    if (seen) {
        counted_photons[2] += 1ul;
    }
}

// What an invocation of a photon kernel does first: its counts zeroed,
// the listed objects and materials read (rt_objects.glsl and
// rt_shading.glsl say why).
void start_photon_invocation() {
    for (int k = 0; k < 4; ++k) {
        counted_photons[k] = 0ul;
    }
    read_listed_objects();
    if (MATERIALS_LISTED) {
        read_listed_materials();
    }
}

// This invocation's counts, added to the render's.
void flush_photon_counts() {
    for (int k = 0; k < 4; ++k) {
        if (counted_photons[k] > 0ul) {
            atomicAdd(photon_counts[k], counted_photons[k]);
        }
    }
}

#endif
