// Screen-linear interpolation (the lecture's scanline rule,
// `interpolation = "screen"`) without GLSL's `noperspective`: the vertex
// stage writes value * w and w as ordinary (perspective-correct) varyings
// and the fragment stage divides. Perspective-correct interpolation of
// value * w over that of w is sum(l_i value_i) / sum(l_i) = sum(l_i value_i)
// for screen-space barycentrics l_i: exactly screen-linear. A triangle the
// near plane clips gets new vertices whose values follow from clip-space
// interpolation of value * w and w; the CPU reference (src/cpu/raster/)
// does the same arithmetic.
//
// Why not `noperspective`: lavapipe 22.3 returned infinities for it on
// triangles that reach far outside the image (the default scene's floor).
#ifndef SCREEN_LINEAR_GLSL
#define SCREEN_LINEAR_GLSL

#endif
