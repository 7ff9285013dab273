#pragma once
// A solid's per-particle vectors (positions, link vectors, momenta) are stored with as many
// components as the solid has dimensions: every z component of a 2D solid is zero (its bodies,
// loads and fluid have none), and not storing it cuts the memory each step moves by about a third.
// This reads such an array as Vec3s, or its x and y components as a pair.
#include "solid/solid_topology.h"

namespace lbsolid::solid {

struct ParticleVectors {
  const double* data = nullptr;
  int dimension = 3;  // components per vector
  Vec3 operator[](long i) const {
    const double* v = data + i * dimension;
    return dimension == 2 ? Vec3{v[0], v[1], 0.0} : Vec3{v[0], v[1], v[2]};
  }
  // The same where the dimension D is known at compile time (hot loops).
  template <int D>
  Vec3 get(long i) const {
    const double* v = data + i * D;
    if constexpr (D == 2) return {v[0], v[1], 0.0};
    else return {v[0], v[1], v[2]};
  }
};

// The x and y components of a stored vector as one SSE2 value: the solid's step does the same
// operations on them two at a time (z, in 3D, alone). What is read as a pair should be written
// as one: a pair loaded from two scalar stores just made waits for both (no store forwarding);
// the links alone in pairs, the bases still stored one by one, made the solid stage 0.7-0.9 ns
// a particle slower.
// Read and written as a vector of doubles, which GCC lets alias only doubles: through memcpy (as
// before) each store might have changed any object, so what the solid's step had read before it
// (array addresses, the stage's members) was read again after it (the solid stage -0.3 to -0.7
// ns a particle in 2D, separate processes run alternately).
using XyPair = double __attribute__((vector_size(16)));
// (A typedef: Clang ignores the alignment in a `using` alias, and the pair then needs 16 bytes.)
typedef double UnalignedXyPair __attribute__((vector_size(16), aligned(alignof(double))));
inline XyPair load_xy(const double* v) { return *reinterpret_cast<const UnalignedXyPair*>(v); }
inline void store_xy(double* v, XyPair p) { *reinterpret_cast<UnalignedXyPair*>(v) = p; }

}  // namespace lbsolid::solid
