// The photon map's four stages (caustics.comp.glsl): the twin of
// src/cpu/caustics/sppm.rs and photons.rs, in the order of
// docs/lighting-model.md, "Caustics: light the eye's rays cannot find".
// Its own interface (the pass's push constants, set 1) is here: only
// caustics.comp.glsl, compiled with FORWARD, includes this.
#ifndef RT_CAUSTICS_GLSL
#define RT_CAUSTICS_GLSL

#include "rt_interface.glsl"
#include "film_fixed.glsl"
#include "random_streams.glsl"
#include "rt_ray.glsl"
#include "rt_packet.glsl"
#include "rt_search.glsl"
#include "rt_surface.glsl"
#include "rt_shading.glsl"
#include "rt_children.glsl"
#include "rt_photon.glsl"

// The dispatch (gpu::raytrace::caustics::CausticPass).
layout(push_constant) uniform CausticPass {
    uint first;            // the pass's first photon
    uint count;            // its photons
    uint total;            // photons per pass, over which the lights' power is split
    uint stage;            // 0 visible points, 1 grid, 2 photons, 3 update
    uint pass;             // the pass's number, which keys the eye paths' numbers
    uint buckets;          // the grid's hash buckets
    float initial_radius;  // in pixel footprints
    float alpha;           // SPPM's share of new photons kept
} batch;

// Each pixel's visible point this pass, three quads: xyz its position and
// w its radius (negative: none this pass); xyz the normal on the side it
// faces; xyz its weight, the eye path's weights times kd C.
layout(std430, set = 1, binding = 0) buffer VisiblePointBuffer { vec4 points[]; };
// Each pixel's state over the passes, two quads: rgb its flux so far and
// w its count of photons kept; x its radius (0 until it has had a point).
layout(std430, set = 1, binding = 1) buffer PixelStateBuffer { vec4 states[]; };
// The grid: the widest radius of the pass (as the bits of a float, which
// order as the floats do for radii of 0 or more), the nodes used, and
// each bucket's first node.
layout(std430, set = 1, binding = 2) buffer GridBuffer {
    uint grid_widest;
    uint grid_nodes;
    uint grid_unused0;
    uint grid_unused1;
    uint heads[];
};
// A bucket's list: x a pixel, y the next node.
layout(std430, set = 1, binding = 3) buffer GridNodeBuffer { uvec2 nodes[]; };
// Each pixel's photons gathered this pass.
layout(std430, set = 1, binding = 4) buffer FoundBuffer { uint found[]; };

const uint NO_NODE = 0xffffffffu;

// What a surface does to light at a hit: its albedo kd C (tinted).
vec3 albedo_at(Hit hit, Surfel s, Surface m, vec3 dir) {
    vec3 tint = vec3(1.0);
    if (VERTEX_COLORS) {
        tint *= hit_tint(hit);
    }
    if (PATTERNS) {
        tint *= hit_pattern(hit, s, dir, 0.0);
    }
    return m.kd * m.color * tint;
}

// Pixel `pixel`'s eye path this pass, if `live`: through a point of the
// pixel drawn at level 0 of its eye path's numbers (`start_eye_path`),
// then at each surface one event drawn at the next level: stop on its kd C (all
// paths where it has no kr or kt, half where it has), or go on by kr or
// kt in proportion, each weighted up by its chance. The point it stops
// on is written, its radius set where the pixel has none yet. Call in
// uniform control flow (the searches walk the BVH as packets).
void trace_visible_point(uint pixel, bool live) {
    uint width = frame.image.x;
    Sampler eye = start_eye_path(pixel, batch.pass);
    vec2 at = vec2(float(pixel % width), float(pixel / width)) + sampler_at_level(eye, 0).xy;
    vec2 ndc = at * vec2(2.0 / float(width), 2.0 / float(frame.image.y)) - 1.0;
    float focal = frame.right_focal.w;
    vec3 dir = normalize(frame.forward_cutoff.xyz + frame.right_focal.xyz * (ndc.x * frame.up_aspect.w / focal) -
                         frame.up_aspect.xyz * (ndc.y / focal));
    vec3 origin = vec3(0.0);
    vec3 weight = vec3(1.0);
    float travelled = 0.0;
    bool stops = false;
    vec3 position = vec3(0.0);
    vec3 normal = vec3(0.0);
    int depth = int(frame.image.w);
    for (int level = 0;; ++level) {
        Hit hit = nearest(origin, dir, live);
        live = live && hit.shape != NO_SHAPE;
        if (live) {
            Surfel s = resolve(origin, dir, hit);
            MaterialRecord material = material_at(s.material);
            vec3 albedo = albedo_at(hit, s, surface_of(material), dir);
            travelled += hit.t;
            Children c = children_of(Ray(origin, dir, 1.0, 0), s.normal, material, 0.0);
            float p_reflect = c.reflects ? c.reflect_weight : 0.0;
            float p_refract = c.refracts ? c.refract_weight : 0.0;
            float p_stop = albedo == vec3(0.0) ? 0.0 : (p_reflect + p_refract > 0.0 ? 0.5 : 1.0);
            float pick = sampler_at_level(eye, level + 1).x;
            live = s.normal != vec3(0.0);
            if (live && pick < p_stop) {
                stops = true;
                position = s.p;
                normal = dot(s.geometric, dir) > 0.0 ? -s.normal : s.normal;
                weight *= albedo / p_stop;
                live = false;
            } else if (live) {
                float scale = max(p_reflect + p_refract, 1.0);
                float event = (pick - p_stop) / (1.0 - p_stop) * scale;
                vec3 next = event < p_reflect ? dir - 2.0 * dot(dir, s.normal) * s.normal : c.refract_dir;
                live = event < p_reflect + p_refract && level < depth;
                weight *= scale / (1.0 - p_stop);
                origin = offset_origin(s.p, origin, s.geometric, next);
                dir = next;
            }
        }
        if (!(HAS_BVH ? packet_any(live) : live)) {
            break;
        }
    }
    if (pixel >= frame.image.x * frame.image.y) {
        return;
    }
    float radius = states[2u * pixel + 1u].x;
    if (stops && radius == 0.0) {
        radius = batch.initial_radius * travelled * 2.0 / (frame.right_focal.w * float(frame.image.y));
        states[2u * pixel + 1u].x = radius;
    }
    stops = stops && radius > 0.0;
    points[3u * pixel] = vec4(position, stops ? radius : -1.0);
    points[3u * pixel + 1u] = vec4(normal, 0.0);
    points[3u * pixel + 2u] = vec4(weight, 0.0);
    if (stops) {
        atomicMax(grid_widest, floatBitsToUint(radius));
    }
}

// The grid's cell edge: twice the widest radius (a little more, so that
// rounding cannot make a point's box span three cells).
float grid_cell() {
    return 2.001 * uintBitsToFloat(grid_widest);
}

// The cell of p, each coordinate held within 2^30 (a point that far out in
// cells only shares a crowded bucket).
ivec3 cell_of(vec3 p, float cell) {
    return ivec3(clamp(floor(p / cell), vec3(-1073741824.0), vec3(1073741824.0)));
}

uint bucket_of(ivec3 c) {
    uvec3 u = uvec3(c);
    return ((u.x * 73856093u) ^ (u.y * 19349663u) ^ (u.z * 83492791u)) % batch.buckets;
}

// Puts pixel `pixel`'s visible point into the bucket of each cell its
// radius's box overlaps (at most two a side), once a bucket.
void insert_point(uint pixel) {
    vec4 point = points[3u * pixel];
    if (!(point.w > 0.0)) {
        return;
    }
    float cell = grid_cell();
    ivec3 lo = cell_of(point.xyz - point.w, cell);
    ivec3 hi = min(cell_of(point.xyz + point.w, cell), lo + 1);
    uint used[8];
    int n = 0;
    for (int z = lo.z; z <= hi.z; ++z) {
        for (int y = lo.y; y <= hi.y; ++y) {
            for (int x = lo.x; x <= hi.x; ++x) {
                uint b = bucket_of(ivec3(x, y, z));
                bool again = false;
                for (int k = 0; k < n; ++k) {
                    again = again || used[k] == b;
                }
                if (!again) {
                    used[n] = b;
                    n += 1;
                    uint node = atomicAdd(grid_nodes, 1u);
                    nodes[node] = uvec2(pixel, atomicExchange(heads[b], node));
                }
            }
        }
    }
}

// A photon of flux `flux` landed at `p`, on the side `n` faces: added,
// times their weights, to the visible points within their radius that
// face the same side (the host's `gather`).
void gather(vec3 p, vec3 n, vec3 flux) {
    float cell = grid_cell();
    if (!(cell > 0.0)) {
        return;
    }
    for (uint node = heads[bucket_of(cell_of(p, cell))]; node != NO_NODE; node = nodes[node].y) {
        uint pixel = nodes[node].x;
        vec4 point = points[3u * pixel];
        vec3 d = p - point.xyz;
        if (dot(d, d) < point.w * point.w && dot(n, points[3u * pixel + 1u].xyz) > 0.0) {
            add_to_film(pixel, flux * points[3u * pixel + 2u].xyz);
            atomicAdd(found[pixel], 1u);
            counted_photons[1] += 1ul;
        }
    }
}

// Caustic photon i's flight, if `live`: the forward tracer's photon, sent
// on from its first surface only by a mirror or glass event, from the
// others by any (diffuse bounces up to the scene's), gathered at every
// surface with kd C that it reaches after its first
// (cpu::caustics::trace_caustic_photon). Call in uniform control flow.
void trace_caustic_photon(uint i, bool live) {
    Flight f = emit_photon(i, batch.total);
    if (live) {
        counted_photons[0] += 1ul;
    }
    int depth = int(frame.image.w);
    for (int level = 0;; ++level) {
        Hit hit = nearest(f.origin, f.dir, live);
        live = live && hit.shape != NO_SHAPE;
        Surfel s = Surfel(vec3(0.0), vec3(0.0), vec3(0.0), 0u);
        MaterialRecord material = MaterialRecord(vec4(0.0), vec4(0.0), vec2(0.0));
        vec3 albedo = vec3(0.0);
        vec3 arriving = f.flux;
        if (live) {
            counted_photons[3] += 1ul;
            s = resolve(f.origin, f.dir, hit);
            material = material_at(s.material);
            albedo = albedo_at(hit, s, surface_of(material), f.dir);
            if (!f.falloff_applied) {
                arriving = f.flux * falloff_factor(f.travelled + hit.t);
            }
            live = s.normal != vec3(0.0);
            if (live && level > 0 && albedo != vec3(0.0)) {
                counted_photons[2] += 1ul;
                gather(s.p, dot(s.geometric, f.dir) > 0.0 ? -s.normal : s.normal, arriving);
            }
        }
        if (albedo != vec3(0.0)) {
            f.diffuse_vertices += 1;
        }
        // Light that leaves its first surface diffusely is the backward
        // tracer's (its shadow rays find that surface's light).
        live = live && level < depth &&
               go_on(f, s, material, albedo, arriving, photon_numbers(i, level + 1), level > 0);
        if (!(HAS_BVH ? packet_any(live) : live)) {
            break;
        }
    }
}

// Pixel `pixel` after a pass: SPPM's update where it gathered photons
// (n' = n + alpha m, r' = r sqrt(n' / (n + m)), the flux scaled by
// (r' / r)^2), then the pass's sums and its share of the grid cleared
// for the next pass.
void update_pixel(uint pixel) {
    uint m = found[pixel];
    if (m > 0u) {
        vec4 state = states[2u * pixel];
        vec3 flux = vec3(float(film[3u * pixel]), float(film[3u * pixel + 1u]), float(film[3u * pixel + 2u])) *
                    (1.0 / FILM_ONE);
        float count = state.w + batch.alpha * float(m);
        float shrink = count / (state.w + float(m));
        states[2u * pixel] = vec4((state.rgb + flux) * shrink, count);
        states[2u * pixel + 1u].x *= sqrt(shrink);
        for (uint c = 0u; c < 3u; ++c) {
            film[3u * pixel + c] = 0ul;
        }
        found[pixel] = 0u;
    }
    for (uint b = 2u * pixel; b < min(2u * pixel + 2u, batch.buckets); ++b) {
        heads[b] = NO_NODE;
    }
    if (pixel == 0u) {
        grid_widest = 0u;
        grid_nodes = 0u;
    }
}

#endif
