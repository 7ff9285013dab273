// lbsolid-observer-bench: what the daemon's observers cost beside a step, on one thread: the
// velocity profile (streamed by WatchProfiles, u_x averaged along each row) and a whole field read
// (GetField and field snapshots: density and velocity of every node, row by row). The grid is the
// load benchmark's background session (192 x 96 D2Q9, double), whose profile streams showed up
// under load (issue 12), and a 3D box for comparison. Best of --repeats rounds.
//   lbsolid-observer-bench [--repeats 5]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "fluid/fluid_lattice.h"
#include "lattice/d2q9.h"
#include "lattice/d3q19.h"
#include "observe/velocity_profile.h"

namespace {

using namespace lbsolid;
using Clock = std::chrono::steady_clock;

// Microseconds per call of fn, the best of `repeats` rounds of `calls` calls.
template <class Fn>
double best_us(int repeats, int calls, const Fn& fn) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    for (int k = 0; k < calls; ++k) fn();
    best = std::min(best, std::chrono::duration<double, std::micro>(Clock::now() - start).count() / calls);
  }
  return best;
}

template <class L>
void measure(const char* name, int nx, int ny, int nz, int repeats) {
  fluid::FluidConfig c;
  c.nx = nx, c.ny = ny, c.nz = nz;
  c.sides[fluid::kYLow].kind = fluid::WallKind::kBounceBack;
  c.sides[fluid::kYHigh].kind = fluid::WallKind::kBounceBack;
  c.body_force = {1e-6, 0, 0};
  fluid::FluidLattice<L, double> f(c);
  f.initialize([](int, int, int) { return 1.0; }, [](int, int y, int) { return fluid::Vec3{1e-3 * y, 0, 0}; });
  f.run(11);  // an odd count: the in-place scheme's odd-step reads are the costlier ones
  double sink = 0;
  const double step = best_us(repeats, 20, [&] { f.run(1); });
  const double profile = best_us(repeats, 50, [&] { sink += observe::velocity_profile(f)[1]; });
  std::vector<double> density(nx), velocity(3 * static_cast<std::size_t>(nx));
  const double field = best_us(repeats, 20, [&] {
    for (int z = 0; z < nz; ++z)
      for (int y = 0; y < ny; ++y) f.row_moments(y, z, 0, nx, density.data(), velocity.data());
    sink += velocity[3];
  });
  const double nodes = static_cast<double>(nx) * ny * nz;
  std::printf("%-6s %4d x %3d x %3d: step %8.1f us | profile %8.1f us (%.2f ns/node, %.2f steps) | field read %8.1f us "
              "(%.2f ns/node, %.2f steps)%s\n",
              name, nx, ny, nz, step, profile, 1e3 * profile / nodes, profile / step, field, 1e3 * field / nodes,
              field / step, sink == 12345.678 ? " " : "");
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 5;
  for (int k = 1; k < argc; ++k) {
    if (!std::strcmp(argv[k], "--repeats") && k + 1 < argc) {
      repeats = std::max(1, std::atoi(argv[++k]));
    } else {
      std::fprintf(stderr, "usage: lbsolid-observer-bench [--repeats N]\n");
      return 2;
    }
  }
  measure<lattice::D2Q9>("D2Q9", 192, 96, 1, repeats);
  measure<lattice::D3Q19>("D3Q19", 64, 64, 64, repeats);
}
