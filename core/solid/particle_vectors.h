#pragma once
// A solid's per-particle vectors (positions, link vectors, momenta) are stored with as many
// components as the solid has dimensions: every z component of a 2D solid is zero (its bodies,
// loads and fluid have none), and not storing it cuts the memory each step moves by about a third.
// This reads such an array as Vec3s.
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

}  // namespace lbsolid::solid
