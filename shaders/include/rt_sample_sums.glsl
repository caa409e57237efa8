// The backward tracer's samples, with diffuse bounces (PATHS), summed as
// the forward tracer's splats are (film_fixed.glsl): each sample's value
// over the pixel's samples, rounded to the fixed point, added as an
// integer. The sums do not depend on how the samples were split between
// dispatches, runs or machines (`render --shard`), so the parts of a
// render add up to its image bit for bit.
//
// Without 64-bit integers in the shader (a device need not have them), a
// sum is two words, low first: on a little-endian host the buffer reads
// back as 64-bit words (film_sums::FilmSums::from_ne_bytes).

#ifndef RT_SAMPLE_SUMS_GLSL
#define RT_SAMPLE_SUMS_GLSL

#include "rt_interface.glsl"
#include "film_fixed.glsl"

// Adds b to a, two words each, low first, wrapping as a 64-bit sum would.
// The low word carries where it wrapped below either term (not with
// uaddCarry: naga, which checks every module, cannot read it).
uvec2 add_words(uvec2 a, uvec2 b) {
    uint low = a.x + b.x;
    return uvec2(low, a.y + b.y + uint(low < a.x));
}

// A sample's value, already divided by the samples, in fixed point:
// (value * FILM_ONE + 0.5) truncated, as two words. The high word is the
// whole 2^32s in it: subtracting them leaves a float below 2^32 exactly
// (both are multiples of the value's last place).
uvec2 fixed_words(float value) {
    float scaled = value * FILM_ONE;
    if (!(scaled >= 0.5 && scaled <= FILM_MAX)) {
        return uvec2(0u);
    }
    float rounded = scaled + 0.5;
    float high = floor(rounded * (1.0 / FILM_ONE));
    return uvec2(uint(rounded - high * FILM_ONE), uint(high));
}

// Adds a sample's value, divided by the pixel's samples, to a pixel's sums.
void add_sample(inout uvec2 sums[3], vec3 share) {
    for (int c = 0; c < 3; ++c) {
        sums[c] = add_words(sums[c], fixed_words(share[c]));
    }
}

// Adds a pixel's sums of this dispatch's samples to its sums in the
// buffer. One lane has the pixel in a dispatch, and dispatches are ordered
// by barriers: a plain read and write, no atomics.
void add_to_pixel(uint pixel, uvec2 sums[3]) {
    uint at = 3u * pixel;
    for (uint c = 0u; c < 3u; ++c) {
        sample_sums[at + c] = add_words(sample_sums[at + c], sums[c]);
    }
}

#endif
