// The random numbers every kernel draws: the twin of src/random_streams.rs,
// name for name and bit for bit (its unit test reads the stream constants
// below and holds them to the Rust ones). Numbers are counter-based: each
// draw hashes a key of four words, the last of which names the stream, so
// that a path's numbers are a function of what it is (a pixel's sample, a
// photon) and not of the lane, subgroup, dispatch or machine that traces
// it. The streams, and which key each hashes:
#ifndef RANDOM_STREAMS_GLSL
#define RANDOM_STREAMS_GLSL

// Diffuse bounces of the backward tracer (PATHS): (pixel, sample, level);
// words 0 and 1 the bounce's direction, 2 its Russian roulette.
const uint STREAM_BOUNCE = 0u;
// Photons of the forward tracer and the photon map: (photon, level, 0);
// at level 0 the light, and the direction; after, the event at the
// level-th surface.
const uint STREAM_PHOTON = 2u;
// The photon map's eye paths: (pixel, pass, level); at level 0 the point
// of the pixel, after, the event at the level-th surface.
const uint STREAM_CAUSTIC_EYE = 3u;
// The scramble seeds of a path-traced pixel's samples
// (rt_pixel_samples.glsl): (pixel, i & 1, 0), one per stream of samples.
const uint STREAM_PIXEL_SCRAMBLE = 5u;

// Jarzynski and Olano's 4-D hash (2020): a counter in, four words out.
uvec4 pcg4d(uvec4 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    return v;
}

// The four words of `stream` at key (a, b, c).
uvec4 stream_words(uint stream, uint a, uint b, uint c) {
    return pcg4d(uvec4(a, b, c, stream));
}

// The four words a path of `stream` whose key starts `path` draws at
// `level`. The photons' keys put the level second, the others third.
uvec4 path_words(uint stream, uvec2 path, int level) {
    if (stream == STREAM_PHOTON) {
        return stream_words(stream, path.x, uint(level), path.y);
    }
    return stream_words(stream, path.x, path.y, uint(level));
}

// Words as numbers in [0, 1): the top 24 bits of each, exact in f32 (the
// CPU's f64 starts from the same values).
vec4 unit_numbers(uvec4 words) {
    return vec4(words >> 8u) * (1.0 / 16777216.0);
}

// A path's numbers, in the spirit of pbrt's samplers (the twin of
// `random_streams::Sampler`): started for a pixel's sample, a photon or an
// eye path of the photon map, then drawn from level by level.
struct Sampler {
    uint stream;
    uvec2 path;  // (pixel, sample), (photon, 0) or (pixel, pass)
};

Sampler start_pixel_sample(uint pixel, uint sample_index) {
    return Sampler(STREAM_BOUNCE, uvec2(pixel, sample_index));
}

Sampler start_photon(uint photon) {
    return Sampler(STREAM_PHOTON, uvec2(photon, 0u));
}

Sampler start_eye_path(uint pixel, uint pass) {
    return Sampler(STREAM_CAUSTIC_EYE, uvec2(pixel, pass));
}

// The four numbers in [0, 1) the path draws at `level`.
vec4 sampler_at_level(Sampler source, int level) {
    return unit_numbers(path_words(source.stream, source.path, level));
}

#endif
