// The fixed point that films are summed in (src/film_sums.rs): FILM_ONE is
// 1.0 (2^32), so a term keeps 2^-32 of absolute precision and a pixel holds
// sums up to 2^31 (far past any image's values). A term is clamped below
// FILM_MAX, so that one absurd term cannot wrap a pixel's sum; one that is
// not finite, or under half a unit, adds nothing.
#ifndef FILM_FIXED_GLSL
#define FILM_FIXED_GLSL
const float FILM_ONE = 4294967296.0;
const float FILM_MAX = 9.0e18;

#endif
