#pragma once
// The fluid node nearest to an off-lattice position, on the lattice's own geometry (MODEL.md
// section 3): square/cubic rounding on D2Q9 and D3Q19; on D2Q7 the nearest point of the triangular
// grid, which lies in one of the two rows around the position. Periodic axes wrap; walled axes
// clamp to the first or last node.
// Any double is accepted (a diverging particle reaches NaN or 1e300 between two monitor checks):
// each coordinate is first clamped to +-2^40, far beyond any grid, so the casts to long below are
// defined; +-inf and huge values then behave as positions just outside the box (the first or last
// node of a walled axis, some node of a periodic one), and a NaN coordinate is read as 0.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "fluid/fluid_config.h"
#include "fluid/force_inline.h"

namespace lbsolid::coupling {

using Node = std::array<int, 3>;

// A position's coordinate clamped to +-2^40 (which leaves the rounding below exact, a double's
// step there being 2^-12, and i % n free of overflow), NaN, which equals nothing, read as 0.
// Written with min, max and a select so that it compiles without branches (a locate per particle
// per step); force-inlined into each instruction set's copy of nearest_cells().
LBSOLID_FORCE_INLINE double finite_coordinate(double v) {
  constexpr double kLimit = 1099511627776.0;
  const double clamped = std::min(std::max(v, -kLimit), kLimit);
  return v == v ? clamped : 0.0;
}

template <class L>
class NodeLocator {
 public:
  explicit NodeLocator(const fluid::FluidConfig& c)
      : n_{c.nx, c.ny, c.nz},
        periodic_{c.sides[fluid::kXLow].kind == fluid::WallKind::kPeriodic,
                  c.sides[fluid::kYLow].kind == fluid::WallKind::kPeriodic,
                  c.sides[fluid::kZLow].kind == fluid::WallKind::kPeriodic} {}

  // Always inlined: called per particle per step, and a call costs as much as the search.
  [[gnu::always_inline]] Node nearest(const fluid::Vec3& position) const {
    if constexpr (!L::hexagonal) {
      Node node{0, 0, 0};
      for (int a = 0; a < L::D; ++a) node[a] = fit(a, nearest_integer(finite_coordinate(position[a])));
      return node;
    } else {
      const double r[2] = {finite_coordinate(position[0]), finite_coordinate(position[1])};
      // A product, not a quotient: a row off by one at a boundary still leaves the nearest row
      // among the two tried (the nearest node lies in a row within h/2 of the position).
      const long below = floor_of(r[1] * (1.0 / L::row_spacing));
      // The nearest node of each of the two rows, then the nearer of the two (the lower one on a
      // tie), chosen without a branch: which row wins is as good as random.
      const auto in_row = [&](long row, long& x, double& d2) {
        const long y = periodic_[1] ? row : fit(1, row);  // a clamped row is measured where it is
        const double shift = 0.5 * static_cast<double>(y & 1);  // ny even: parity survives wrapping
        x = nearest_integer(r[0] - shift);
        const double dx = static_cast<double>(x) + shift - r[0];
        const double dy = static_cast<double>(y) * L::row_spacing - r[1];
        d2 = dx * dx + dy * dy;
        return y;
      };
      long x_low, x_high;
      double d2_low, d2_high;
      const long y_low = in_row(below, x_low, d2_low), y_high = in_row(below + 1, x_high, d2_high);
      // A mask rather than ?: (which GCC compiles to a branch here).
      const long high = -static_cast<long>(d2_high < d2_low);
      return {fit(0, x_low ^ ((x_low ^ x_high) & high)), fit(1, y_low ^ ((y_low ^ y_high) & high)), 0};
    }
  }

  long cell(const Node& node) const {
    return node[0] + static_cast<long>(n_[0]) * (node[1] + static_cast<long>(n_[1]) * node[2]);
  }

  // cells[p] = cell(nearest(r_p)) for p in [first, end), r_p the L::D doubles at positions + L::D p:
  // the same nodes as nearest(), worked out in doubles so that the loop vectorises
  // (node_locator.cpp; 3-4x faster per particle with AVX2 or AVX-512).
  void nearest_cells(const double* positions, long first, long end, std::uint32_t* cells) const;

 private:
  // std::floor for |v| <= 2^40 (finite_coordinate() ensures it), exactly: truncate, then step
  // down where that rounded up. Without SSE4.1 (the default x86-64 target the coupling is built
  // for) std::floor is a libm call, three per D2Q7 particle per step.
  static long floor_of(double v) {
    const long truncated = static_cast<long>(v);
    return truncated - static_cast<long>(static_cast<double>(truncated) > v);
  }
  // Halves round up; unlike std::lround this inlines (it was a library call per particle).
  static long nearest_integer(double v) { return floor_of(v + 0.5); }
  int fit(int axis, long i) const {
    const long n = n_[axis];
    if (!periodic_[axis]) return static_cast<int>(std::clamp(i, 0L, n - 1));
    if (i >= 0 && i < n) return static_cast<int>(i);  // inside the box: no division
    return static_cast<int>(((i % n) + n) % n);
  }
  std::array<int, 3> n_;
  std::array<bool, 3> periodic_;
};

}  // namespace lbsolid::coupling
