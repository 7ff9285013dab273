#pragma once
// D2Q9: rest, 4 axis and 4 diagonal velocities on a square grid (MODEL.md section 1).
#include "lattice/lattice_traits.h"

namespace lbsolid::lattice {

struct D2Q9 {
  static constexpr const char* name = "D2Q9";
  static constexpr int D = 2;
  static constexpr int Q = 9;
  static constexpr bool hexagonal = false;
  static constexpr double cs2 = 1.0 / 3.0;
  static constexpr std::array<Vec3, Q> c = {{{0, 0, 0},
                                             {1, 0, 0},
                                             {0, 1, 0},
                                             {-1, 0, 0},
                                             {0, -1, 0},
                                             {1, 1, 0},
                                             {-1, 1, 0},
                                             {-1, -1, 0},
                                             {1, -1, 0}}};
  static constexpr std::array<double, Q> w = {4.0 / 9,  1.0 / 9,  1.0 / 9,  1.0 / 9, 1.0 / 9,
                                              1.0 / 36, 1.0 / 36, 1.0 / 36, 1.0 / 36};
  static constexpr Offset3 neighbour_offset(int i, int /*row_parity*/) {
    return {static_cast<int>(c[i][0]), static_cast<int>(c[i][1]), 0};
  }
  // Distance between consecutive rows (y direction) in lattice units.
  static constexpr double row_spacing = 1.0;
};

}  // namespace lbsolid::lattice
