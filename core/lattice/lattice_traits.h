#pragma once
// Generic facts derived from a lattice descriptor: opposite and mirrored directions.
// A descriptor is a struct with static constexpr members:
//   D, Q, cs2, w[Q], c[Q][3] (Cartesian velocity), hexagonal,
//   neighbour_offset(i, row_parity) -> index offset {dx, dy, dz} of the node reached along c_i.
#include <array>
#include <cmath>

namespace lbsolid::lattice {

using Vec3 = std::array<double, 3>;
using Offset3 = std::array<int, 3>;

constexpr bool nearly_equal(double a, double b) { return (a - b) * (a - b) < 1e-20; }

// Index of the direction -c_i.
template <class L>
constexpr int opposite(int i) {
  for (int j = 0; j < L::Q; ++j) {
    if (nearly_equal(L::c[j][0], -L::c[i][0]) && nearly_equal(L::c[j][1], -L::c[i][1]) &&
        nearly_equal(L::c[j][2], -L::c[i][2]))
      return j;
  }
  return -1;
}

// Index of c_i with its component along `axis` reversed (specular reflection).
template <class L>
constexpr int mirrored(int i, int axis) {
  for (int j = 0; j < L::Q; ++j) {
    bool same = true;
    for (int a = 0; a < 3; ++a) {
      const double want = a == axis ? -L::c[i][a] : L::c[i][a];
      same = same && nearly_equal(L::c[j][a], want);
    }
    if (same) return j;
  }
  return -1;
}

template <class L>
constexpr std::array<int, L::Q> opposite_table() {
  std::array<int, L::Q> t{};
  for (int i = 0; i < L::Q; ++i) t[i] = opposite<L>(i);
  return t;
}

}  // namespace lbsolid::lattice
