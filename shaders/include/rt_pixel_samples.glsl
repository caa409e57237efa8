// Where each sample of a path-traced pixel looks (compiled with PATHS): two
// interleaved streams (even and odd samples), each the Sobol sequence's
// first two dimensions under a hash-based Owen scramble seeded by the pixel
// and the stream, so any prefix of a pixel's samples covers the pixel and is
// unbiased, and the two streams are independent estimates for --error. The
// twin of src/cpu/raytrace/pixel_samples.rs, bit for bit (docs/raytracing.md,
// "Samples of a pixel").
#ifndef RT_PIXEL_SAMPLES_GLSL
#define RT_PIXEL_SAMPLES_GLSL

#include "random_streams.glsl"

// The Sobol sequence's second dimension: column k is column k - 1 XOR
// itself shifted right by one, from 2^31.
uint sobol_second(uint index) {
    uint column = 0x80000000u;
    uint word = 0u;
    for (; index != 0u; index >>= 1) {
        if ((index & 1u) != 0u) {
            word ^= column;
        }
        column ^= column >> 1;
    }
    return word;
}

// Burley's hash-based Owen scramble: on the reversed word, where the bits
// above a bit are the lower ones, which carries and even products reach
// only upwards.
uint owen_scramble(uint word, uint seed) {
    uint x = bitfieldReverse(word) + seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return bitfieldReverse(x);
}

// Sample i of pixel `pixel` (y * width + x): its offset in (0, 1)^2 from the
// pixel's top-left corner, the centre of one of 2^23 cells per axis, exact
// in f32.
vec2 pixel_sample(uint pixel, uint i) {
    // Reversed: the scramble's top bits take the seed's low ones, where the
    // hash mixes least (the twin says what that did).
    uvec4 seeds = bitfieldReverse(stream_words(STREAM_PIXEL_SCRAMBLE, pixel, i & 1u, 0u));
    uint index = i >> 1;
    uvec2 words = uvec2(owen_scramble(bitfieldReverse(index), seeds.x),
                        owen_scramble(sobol_second(index), seeds.y));
    return vec2(((words >> 9) << 1) | 1u) * (1.0 / 16777216.0);
}

#endif
