#pragma once
// The fluid node nearest to an off-lattice position, on the lattice's own geometry (MODEL.md
// section 3): square/cubic rounding on D2Q9 and D3Q19; on D2Q7 the nearest point of the triangular
// grid, which lies in one of the two rows around the position. Periodic axes wrap; walled axes
// clamp to the first or last node.
// Any double is accepted (a diverging particle reaches NaN or 1e300 between two monitor checks):
// each coordinate is first clamped to +-2^40, far beyond any grid, so the casts to long below are
// defined; +-inf and huge values then behave as positions just outside the box (the first or last
// node of a walled axis, some node of a periodic one), and a NaN coordinate is read as 0.
#include <array>
#include <cmath>

#include "fluid/fluid_config.h"

namespace lbsolid::coupling {

using Node = std::array<int, 3>;

template <class L>
class NodeLocator {
 public:
  explicit NodeLocator(const fluid::FluidConfig& c)
      : n_{c.nx, c.ny, c.nz},
        periodic_{c.sides[fluid::kXLow].kind == fluid::WallKind::kPeriodic,
                  c.sides[fluid::kYLow].kind == fluid::WallKind::kPeriodic,
                  c.sides[fluid::kZLow].kind == fluid::WallKind::kPeriodic} {}

  Node nearest(const fluid::Vec3& position) const {
    if constexpr (!L::hexagonal) {
      Node node{0, 0, 0};
      for (int a = 0; a < L::D; ++a) node[a] = fit(a, nearest_integer(finite(position[a])));
      return node;
    } else {
      const double r[2] = {finite(position[0]), finite(position[1])};
      const long below = static_cast<long>(std::floor(r[1] / L::row_spacing));
      Node best{0, 0, 0};
      double best_d2 = INFINITY;
      for (long row = below; row <= below + 1; ++row) {
        const long y = periodic_[1] ? row : fit(1, row);  // a clamped row is measured where it is
        const double shift = 0.5 * static_cast<double>(y & 1);  // ny even: parity survives wrapping
        const long x = nearest_integer(r[0] - shift);
        const double dx = static_cast<double>(x) + shift - r[0];
        const double dy = static_cast<double>(y) * L::row_spacing - r[1];
        if (dx * dx + dy * dy < best_d2) {
          best_d2 = dx * dx + dy * dy;
          best = {fit(0, x), fit(1, y), 0};
        }
      }
      return best;
    }
  }

  long cell(const Node& node) const {
    return node[0] + static_cast<long>(n_[0]) * (node[1] + static_cast<long>(n_[1]) * node[2]);
  }

 private:
  // 2^40 leaves the rounding exact (a double's step there is 2^-12) and i % n free of overflow.
  static constexpr double kLimit = 1099511627776.0;
  // Written so that NaN, for which every comparison is false, becomes 0.
  static double finite(double v) { return v >= -kLimit ? (v <= kLimit ? v : kLimit) : (v < 0 ? -kLimit : 0.0); }
  // Halves round up; unlike std::lround this inlines (it was a library call per particle).
  static long nearest_integer(double v) { return static_cast<long>(std::floor(v + 0.5)); }
  int fit(int axis, long i) const {
    const long n = n_[axis];
    if (i >= 0 && i < n) return static_cast<int>(i);  // inside the box: no division
    if (periodic_[axis]) return static_cast<int>(((i % n) + n) % n);
    return static_cast<int>(i < 0 ? 0 : n - 1);
  }
  std::array<int, 3> n_;
  std::array<bool, 3> periodic_;
};

}  // namespace lbsolid::coupling
