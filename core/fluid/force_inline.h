#pragma once
// The collision (and the forcing it calls) must be inlined into the cell loop for that loop to
// vectorise, and for the compiler to see each expression whole, as written. The row kernels are
// inlined too, into each instruction set's copy (kernel_isa.h); a lambda says so after its
// parameters: [&](long begin) LBSOLID_FORCE_INLINE_LAMBDA { ... }.
#define LBSOLID_FORCE_INLINE inline __attribute__((always_inline))
#define LBSOLID_FORCE_INLINE_LAMBDA __attribute__((always_inline))
