// NodeLocator::nearest_cells: nearest() for a range of particles, in a loop the compiler
// vectorises. nearest() works in integers (a double -> long conversion per axis and row, and %
// on a periodic axis), which no vector unit before AVX-512 converts and which leaves the loop
// scalar: 12 ns a D2Q7 particle on this project's machines, the largest part of the locate stage.
// Here every step is done in doubles, exactly:
//   - floor(v) is std::floor, which GCC inlines with -fno-trapping-math: one round instruction
//     with SSE4.1 (the AVX2 and AVX-512 paths), a short exact sequence of SSE2 operations on the
//     baseline. (The 1.5 2^52 rounding trick with a select written out here before compiled to
//     mask shuffles on AVX-512: 3.4-3.6 ns a D2Q7 particle against 1.9-2.1, the same cells for
//     every input tried, and the NodeLocator tests, which compare with nearest(), pass on all paths.)
//   - a periodic wrap as i - n floor(i / n), exact for |i| <= 2^41: i / n is an integer or at
//     least 1/n from one, and its rounding error is below 2^-11 / n, so its floor is the true
//     one; the product and the difference are integers below 2^53;
//   - only the node's own coordinates, each below 2^31 (an int), are converted to integers, and its cell
//     (below 2^32) is summed in 32-bit unsigned arithmetic, which is exact there.
// The positions are clamped and NaN read as 0 as nearest() does, so the two give the same node
// for every double (NodeLocator tests). This file is compiled with -fno-trapping-math: it lets
// GCC evaluate both sides of the selects above and vectorise with AVX2 (with trapping math only
// AVX-512's masked instructions qualify); no result changes, only which floating-point status
// flags a discarded side may raise, and nothing reads those flags. The loop runs through
// run_with_isa, so it gets AVX2 or AVX-512 where the CPU has it.
#include "coupling/node_locator.h"

#include <cmath>

#include "fluid/force_inline.h"
#include "fluid/kernel_isa.h"
#include "lattice/d2q7.h"
#include "lattice/d2q9.h"
#include "lattice/d3q19.h"

namespace lbsolid::coupling {

namespace {

// The node index i (an integer in a double) on an axis of n nodes: wrapped or clamped.
template <bool kPeriodic>
LBSOLID_FORCE_INLINE double fit_axis(double i, double n) {
  if constexpr (!kPeriodic) {
    return std::min(std::max(i, 0.0), n - 1.0);
  } else {
    return i - std::floor(i / n) * n;
  }
}
LBSOLID_FORCE_INLINE std::uint32_t to_index(double v) { return static_cast<std::uint32_t>(static_cast<std::int32_t>(v)); }

struct Axes {
  double n[3];
  std::uint32_t row, plane;  // cells per row (nx) and per plane (nx ny)
};

template <class L, bool kPx, bool kPy, bool kPz>
LBSOLID_FORCE_INLINE void nearest_cells_loop(const Axes& axes, const double* __restrict positions, long first,
                                             long end, std::uint32_t* __restrict cells) {
  constexpr int D = L::D;
  for (long p = first; p < end; ++p) {
    const double* r = positions + D * p;
    double node[3] = {0, 0, 0};
    if constexpr (!L::hexagonal) {
      node[0] = fit_axis<kPx>(std::floor(finite_coordinate(r[0]) + 0.5), axes.n[0]);
      node[1] = fit_axis<kPy>(std::floor(finite_coordinate(r[1]) + 0.5), axes.n[1]);
      if constexpr (D == 3) node[2] = fit_axis<kPz>(std::floor(finite_coordinate(r[2]) + 0.5), axes.n[2]);
    } else {
      // nearest()'s search, step by step: the nearest node of the row below and of the row above,
      // then the nearer (the lower on a tie); a periodic row is measured unwrapped.
      const double x = finite_coordinate(r[0]), y = finite_coordinate(r[1]);
      const double below = std::floor(y * (1.0 / L::row_spacing));
      double ys[2] = {below, below + 1};
      if constexpr (!kPy)
        for (double& at : ys) at = fit_axis<false>(at, axes.n[1]);
      // Half a spacing on odd rows. Clamping keeps rows one apart or merges them (both at a
      // wall's row), so the upper row has the lower one's shift (merged) or the other (one floor
      // fewer than working out each row's parity: 1.86 -> 1.67 ns a particle).
      double shifts[2];
      shifts[0] = 0.5 * (ys[0] - 2.0 * std::floor(0.5 * ys[0]));
      shifts[1] = ys[1] == ys[0] ? shifts[0] : 0.5 - shifts[0];
      double xs[2], d2[2];
      for (int k = 0; k < 2; ++k) {
        const double at = ys[k], shift = shifts[k];
        xs[k] = std::floor(x - shift + 0.5);
        const double dx = xs[k] + shift - x;
        const double dy = at * L::row_spacing - y;
        d2[k] = dx * dx + dy * dy;
      }
      const bool high = d2[1] < d2[0];
      node[0] = fit_axis<kPx>(high ? xs[1] : xs[0], axes.n[0]);
      node[1] = fit_axis<kPy>(high ? ys[1] : ys[0], axes.n[1]);
    }
    cells[p] = to_index(node[0]) + axes.row * to_index(node[1]) + axes.plane * to_index(node[2]);
  }
}

template <class L, bool kPx, bool kPy, bool kPz>
void run_nearest_cells(const Axes& axes, const double* positions, long first, long end, std::uint32_t* cells) {
  fluid::run_with_isa(fluid::kernel_isa(), [&]() LBSOLID_FORCE_INLINE_LAMBDA {
    nearest_cells_loop<L, kPx, kPy, kPz>(axes, positions, first, end, cells);
  });
}

}  // namespace

template <class L>
void NodeLocator<L>::nearest_cells(const double* positions, long first, long end, std::uint32_t* cells) const {
  const Axes axes{{static_cast<double>(n_[0]), static_cast<double>(n_[1]), static_cast<double>(n_[2])},
                  static_cast<std::uint32_t>(n_[0]), static_cast<std::uint32_t>(n_[0]) * static_cast<std::uint32_t>(n_[1])};
  // The periodic axes as template arguments: a loop without branches in it.
  const int which = (periodic_[0] ? 1 : 0) | (periodic_[1] ? 2 : 0) | (L::D == 3 && periodic_[2] ? 4 : 0);
  switch (which) {
    case 0: return run_nearest_cells<L, false, false, false>(axes, positions, first, end, cells);
    case 1: return run_nearest_cells<L, true, false, false>(axes, positions, first, end, cells);
    case 2: return run_nearest_cells<L, false, true, false>(axes, positions, first, end, cells);
    case 3: return run_nearest_cells<L, true, true, false>(axes, positions, first, end, cells);
    case 4: return run_nearest_cells<L, false, false, true>(axes, positions, first, end, cells);
    case 5: return run_nearest_cells<L, true, false, true>(axes, positions, first, end, cells);
    case 6: return run_nearest_cells<L, false, true, true>(axes, positions, first, end, cells);
    default: return run_nearest_cells<L, true, true, true>(axes, positions, first, end, cells);
  }
}

template class NodeLocator<lattice::D2Q9>;
template class NodeLocator<lattice::D2Q7>;
template class NodeLocator<lattice::D3Q19>;

}  // namespace lbsolid::coupling
