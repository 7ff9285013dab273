#pragma once
// The bench's scenes (scene_bench.cpp), also built by docs/experiments/in_process_ab.cpp.
#include <algorithm>
#include <cmath>

#include "lattice/d2q7.h"
#include "scene/scene.h"

namespace lbsolid::bench {

using scene::Scene;

// A D2Q7 box periodic in x between bounce-back walls, n x n nodes, the paper's omega = 1.
inline Scene paper_box(int n, int threads) {
  Scene s;
  s.lattice = scene::LatticeKind::kD2Q7;
  s.fluid.threads = threads;
  s.fluid.nx = n;
  s.fluid.ny = n;
  s.fluid.omega = 1.0;
  s.fluid.sides[fluid::kYLow].kind = s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kBounceBack;
  return s;
}

// Square 16x16 sheets on a regular grid of the box until `per_cell` particles per fluid cell.
inline void add_sheets(Scene& s, double per_cell) {
  const long cells = static_cast<long>(s.fluid.nx) * s.fluid.ny;
  const long wanted = static_cast<long>(per_cell * cells);
  const double h = lattice::D2Q7::row_spacing;
  const int side = 16;
  long placed = 0;
  // The sheets' spacing shrinks until `wanted` particles fit (spacing 1 covers one cell each).
  const double spacing = std::min(1.0, std::sqrt(s.fluid.nx * (s.fluid.ny - 2) * h / static_cast<double>(wanted)));
  const double pitch = side * spacing + 0.01;
  for (double y = 1 + 0.5 * pitch; y + 0.5 * pitch < (s.fluid.ny - 1) * h && placed < wanted; y += pitch)
    for (double x = 0.5 * pitch; x + 0.5 * pitch < s.fluid.nx && placed < wanted; x += pitch) {
      solid::BodySpec sheet;
      sheet.size = {side, side, 1};
      sheet.spacing = spacing;
      sheet.centre = {x, y, 0};
      sheet.velocity = {0.01, 0, 0};
      s.bodies.push_back(sheet);
      placed += side * side;
    }
}

// A periodic D3Q19 box of n^3 nodes with balls of radius 4 (about 270 particles each) on a
// regular k x k x k grid: a dilute suspension (issue 15's 3D case: 27 balls in 96^3), or a denser
// one (512 balls in 96^3, 3 cells between neighbours).
inline Scene suspension_3d(int n, int k, int threads) {
  Scene s;
  s.lattice = scene::LatticeKind::kD3Q19;
  s.fluid.threads = threads;
  s.fluid.nx = s.fluid.ny = s.fluid.nz = n;
  s.fluid.omega = 1.0;
  const double pitch = static_cast<double>(n) / k;
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j)
      for (int l = 0; l < k; ++l) {
        solid::BodySpec ball;
        ball.shape = solid::BodyShape::kDisk;
        ball.radius = 4;
        ball.centre = {(i + 0.5) * pitch, (j + 0.5) * pitch, (l + 0.5) * pitch};
        ball.velocity = {0.01, 0, 0};
        s.bodies.push_back(ball);
      }
  return s;
}

}  // namespace lbsolid::bench
