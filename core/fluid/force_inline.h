#pragma once
// The collision (and the forcing it calls) must be inlined into the cell loop for that loop to
// vectorise, and for the compiler to see each expression whole, as written.
#define LBSOLID_FORCE_INLINE inline __attribute__((always_inline))
