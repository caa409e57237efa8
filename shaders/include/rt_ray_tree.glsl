// The ray tracer's recursion: reflection and refraction, one sample's ray
// tree walked with a stack of the rays that wait.

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
    return local_shading(s, surface, ray.origin, ray.dir, hits);
}

// What a hit's ray branches into: a reflected ray, a refracted one (its
// direction), both or neither, with their weights. A child lighter than
// the cut-off is pruned (and counted).
struct Children {
    bool reflects;
    float reflect_weight;
    bool refracts;
    vec3 refract_dir;
    float refract_weight;
};

Children children_of(Ray ray, vec3 N, MaterialRecord material, float cutoff) {
    float kr = material.kd_ks_p_kr.w;
    // Decided by kr and total internal reflection, not by the
    // weight, as on the CPU: a weight that underflows in f32 is
    // still a child (pruned).
    Children c = Children(kr > 0.0, ray.weight * kr, false, vec3(0.0), 0.0);
    if (HAS_TRANSMISSION) {
        float kt = material.kt_ior.x;
        float ior = material.kt_ior.y;
        if (kt > 0.0) {
            bool entering = dot(N, ray.dir) < 0.0;
            vec3 n = entering ? N : -N;
            float eta = entering ? 1.0 / ior : ior;
            float cos_i = -dot(n, ray.dir);
            // sin^2(i) from the part along the surface, not
            // 1 - cos^2(i): the twin in src/cpu/raytrace/secondary_rays.rs.
            vec3 along = ray.dir + cos_i * n;
            float k = 1.0 - eta * eta * dot(along, along);
            if (k < 0.0) {
                c.reflects = true;  // total internal reflection
                c.reflect_weight = ray.weight * (kr + kt);
            } else {
                c.refracts = true;
                c.refract_dir = normalize(eta * along - sqrt(k) * n);
                c.refract_weight = ray.weight * kt;
            }
        }
    }
    if (c.reflects && c.reflect_weight < cutoff) {
        c.reflects = false;
        count(4);
    }
    if (c.refracts && c.refract_weight < cutoff) {
        c.refracts = false;
        count(4);
    }
    return c;
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
Ray child_ray(Ray ray, Surfel s, vec3 dir, float weight) {
    return Ray(offset_origin(s.p, ray.origin, s.geometric, dir), dir, weight, ray.depth + 1);
}

// Whether the packet goes on: some lane has a ray (`live`). Without
// refraction no ray waits, so where nothing was hit the packet is done,
// and a miss costs one vote, not two. Without a BVH, no vote (see
// trace_sample).
bool packet_goes_on_with(bool live, bool packet_hits) {
    bool goes_on;
    if (HAS_BVH) {
        if (HAS_TRANSMISSION) {
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
vec3 trace_sample(vec3 dir, bool live) {
    Ray waiting[STACK_SIZE];
    // Each ray's cone (an image's level of detail): its width at the
    // origin and its growth per unit of distance. Kept beside the rays and
    // touched only with TEXTURES, so that a scene without images carries
    // none of it (its pipeline compiled as fast as before them).
    vec2 waiting_cones[STACK_SIZE];
    int top = 0;
    Ray ray = Ray(vec3(0.0), dir, 1.0, 0);
    vec2 cone = vec2(0.0);
    if (TEXTURES) {
        // A primary cone widens by a pixel's height per unit of distance
        // (level_of_detail::pixel_spread).
        cone.y = 2.0 / (frame.right_focal.w * float(frame.image.y));
    }
    if (live) {
        count(0);
    }
    vec3 total = vec3(0.0);
    int max_depth = int(frame.image.w);
    float cutoff = frame.forward_cutoff.w;
    // The first search without a vote: a packet with no pixel on the
    // image is rare (the image's edges), and its lanes find nothing.
    bool packet_goes_on = true;
    while (packet_goes_on) {
        if (live) {
            deepest = max(deepest, ray.depth);
        }
        Hit hit = nearest(ray.origin, ray.dir, live);
        bool hits = live && hit.shape != NO_SHAPE;
        if (live && !hits) {
            total += ray.weight * frame.background.rgb;
        }
        Surfel s = Surfel(vec3(0.0), vec3(0.0), vec3(0.0), 0u);
        MaterialRecord material = MaterialRecord(vec4(0.0), vec4(0.0), vec2(0.0));
        vec3 local = vec3(0.0);
        // Shading walks shadow rays as packets: the whole subgroup comes
        // here, or none of it (where every ray left the scene). With no
        // BVH nothing below shuffles, so each lane goes its own way and
        // the driver's masks do what the votes did, for less (a vote is
        // three shuffles; the four spheres took 0.9x the time without).
        bool packet_hits = HAS_BVH ? packet_any(hits) : hits;
        if (packet_hits) {
            local = shade_hit(ray, hit, hits, cone, s, material);
        }
        live = false;
        if (hits) {
            total += ray.weight * local;
            // Specialization constants appear only as whole conditions: naga's
            // SPIR-V reader rejects operators on them (OpSpecConstantOp).
            bool may_branch = false;
            if (HAS_REFLECTION) {
                // No children from a zero normal: no direction to reflect
                // or refract about.
                may_branch = ray.depth < max_depth && s.normal != vec3(0.0);
            }
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
        if (HAS_TRANSMISSION && !live && top > 0) {
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
