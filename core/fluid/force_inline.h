#pragma once
// The collision (and the forcing it calls) must be inlined into the cell loop for that loop to
// vectorise, and for the compiler to see each expression whole, as written. The row kernels are
// inlined too, into each instruction set's copy (kernel_isa.h); a lambda says so after its
// parameters: [&](long begin) LBSOLID_FORCE_INLINE_LAMBDA { ... }.
// With -DLBSOLID_FORCE_INLINE=OFF (LBSOLID_NO_FORCE_INLINE; the fuzz and TSan builds) inlining is
// left to the compiler: with it forced, clang took 387 s over the kernels' file under ASan, 44 s
// without. The results do not change: -ffp-contract=off keeps every expression rounded as
// written, inlined or not.
#ifdef LBSOLID_NO_FORCE_INLINE
#define LBSOLID_FORCE_INLINE inline
#define LBSOLID_FORCE_INLINE_LAMBDA
#else
#define LBSOLID_FORCE_INLINE inline __attribute__((always_inline))
#define LBSOLID_FORCE_INLINE_LAMBDA __attribute__((always_inline))
#endif
