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

// s + c_{I,A} v, with c = 0 and c = +-1 resolved at compile time: a compiler may not drop `x * 0`
// itself (NaN * 0 is NaN), and on D3Q19 those products are most of a moment's arithmetic. For finite
// v the result is that of s + c v (1 v and -1 v are exact, and adding a zero to a sum that started
// from a zero or a number changes nothing).
template <class L, int I, int A, class T>
inline T add_c(T s, T v) {
  constexpr double c = L::c[I][A];
  if constexpr (c == 0.0) return s;
  else if constexpr (c == 1.0) return s + v;
  else if constexpr (c == -1.0) return s - v;
  else return s + T(c) * v;
}

template <class L>
constexpr std::array<int, L::Q> opposite_table() {
  std::array<int, L::Q> t{};
  for (int i = 0; i < L::Q; ++i) t[i] = opposite<L>(i);
  return t;
}

}  // namespace lbsolid::lattice
