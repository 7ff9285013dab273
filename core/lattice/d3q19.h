#pragma once
// D3Q19: rest, 6 axis and 12 edge velocities on a cubic grid (MODEL.md section 1).
#include "lattice/lattice_traits.h"

namespace lbsolid::lattice {

struct D3Q19 {
  static constexpr const char* name = "D3Q19";
  static constexpr int D = 3;
  static constexpr int Q = 19;
  static constexpr bool hexagonal = false;
  static constexpr double cs2 = 1.0 / 3.0;
  static constexpr std::array<Vec3, Q> c = {{{0, 0, 0},   {1, 0, 0},   {-1, 0, 0},  {0, 1, 0},
                                             {0, -1, 0},  {0, 0, 1},   {0, 0, -1},  {1, 1, 0},
                                             {-1, -1, 0}, {1, -1, 0},  {-1, 1, 0},  {1, 0, 1},
                                             {-1, 0, -1}, {1, 0, -1},  {-1, 0, 1},  {0, 1, 1},
                                             {0, -1, -1}, {0, 1, -1},  {0, -1, 1}}};
  static constexpr std::array<double, Q> w = {
      1.0 / 3,  1.0 / 18, 1.0 / 18, 1.0 / 18, 1.0 / 18, 1.0 / 18, 1.0 / 18,
      1.0 / 36, 1.0 / 36, 1.0 / 36, 1.0 / 36, 1.0 / 36, 1.0 / 36, 1.0 / 36,
      1.0 / 36, 1.0 / 36, 1.0 / 36, 1.0 / 36, 1.0 / 36};
  static constexpr Offset3 neighbour_offset(int i, int /*row_parity*/) {
    return {static_cast<int>(c[i][0]), static_cast<int>(c[i][1]), static_cast<int>(c[i][2])};
  }
  static constexpr double row_spacing = 1.0;
};

}  // namespace lbsolid::lattice
