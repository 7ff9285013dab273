#pragma once
// A solid's per-particle vectors (positions, link vectors, momenta) are stored with as many
// components as the solid has dimensions: every z component of a 2D solid is zero (its bodies,
// loads and fluid have none), and not storing it cuts the memory each step moves by about a third.
// This reads such an array as Vec3s, or its x and y components as a pair.
#include <cstring>

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
using XyPair = double __attribute__((vector_size(16)));
inline XyPair load_xy(const double* v) {
  XyPair p;
  std::memcpy(&p, v, sizeof p);
  return p;
}
inline void store_xy(double* v, XyPair p) { std::memcpy(v, &p, sizeof p); }

}  // namespace lbsolid::solid
