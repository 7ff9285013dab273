#pragma once
// D2Q7: the paper's hexagonal lattice, rest + 6 unit velocities at 60 degrees (MODEL.md section 1).
// Stored as an nx x ny array whose odd rows are shifted right by half a cell: node (x, y) sits at
// (x + (y mod 2)/2, y sqrt(3)/2), so the index offset to a neighbour depends on the row's parity.
#include "lattice/lattice_traits.h"

namespace lbsolid::lattice {

struct D2Q7 {
  static constexpr const char* name = "D2Q7";
  static constexpr int D = 2;
  static constexpr int Q = 7;
  static constexpr bool hexagonal = true;
  static constexpr double cs2 = 1.0 / 4.0;
  static constexpr double half_sqrt3 = 0.86602540378443864676;
  // Directions: rest, then 0, 60, 120, 180, 240, 300 degrees.
  static constexpr std::array<Vec3, Q> c = {{{0, 0, 0},
                                             {1, 0, 0},
                                             {0.5, half_sqrt3, 0},
                                             {-0.5, half_sqrt3, 0},
                                             {-1, 0, 0},
                                             {-0.5, -half_sqrt3, 0},
                                             {0.5, -half_sqrt3, 0}}};
  static constexpr std::array<double, Q> w = {1.0 / 2,  1.0 / 12, 1.0 / 12, 1.0 / 12,
                                              1.0 / 12, 1.0 / 12, 1.0 / 12};
  // A node of an even row reaches the odd row above/below at index x (right) or x-1 (left);
  // a node of an odd row reaches index x+1 (right) or x (left).
  static constexpr Offset3 neighbour_offset(int i, int row_parity) {
    constexpr std::array<Offset3, Q> even = {
        {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}, {0, -1, 0}}};
    constexpr std::array<Offset3, Q> odd = {
        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}, {1, -1, 0}}};
    return row_parity == 0 ? even[i] : odd[i];
  }
  static constexpr double row_spacing = half_sqrt3;
};

}  // namespace lbsolid::lattice
