// The fluid demo: a body-force-driven channel between no-slip walls, run from rest to steady
// state, printed row by row beside the analytic parabola u(y) = g/(2 nu) (y - y0)(y1 - y).
//   lbsolid-channel-demo [--lattice D2Q9|D2Q7|D3Q19] [--precision double|float] [--width N]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "fluid/fluid_lattice.h"
#include "lattice/d2q7.h"
#include "lattice/d2q9.h"
#include "lattice/d3q19.h"

namespace {

using namespace lbsolid;

struct Options {
  std::string lattice = "D2Q9";
  std::string precision = "double";
  int width = 32;
};

template <class L, class T>
int run(const Options& opt) {
  fluid::FluidConfig c;
  c.nx = 4;
  c.ny = opt.width;
  c.nz = L::D == 3 ? 4 : 1;
  c.omega = 1.0;
  c.sides[fluid::kYLow].kind = fluid::WallKind::kBounceBack;
  c.sides[fluid::kYHigh].kind = fluid::WallKind::kBounceBack;
  const double nu = (1.0 / c.omega - 0.5) * L::cs2;
  const double y0 = -0.5 * L::row_spacing, y1 = (opt.width - 0.5) * L::row_spacing;
  const double u_max = 0.02;
  const double g = 8 * nu * u_max / ((y1 - y0) * (y1 - y0));
  c.body_force = {g * c.rho0, 0, 0};
  fluid::FluidLattice<L, T> fluid(c);

  auto profile = [&] {
    std::vector<double> p(c.ny, 0.0);
    for (int y = 0; y < c.ny; ++y) {
      for (int z = 0; z < c.nz; ++z)
        for (int x = 0; x < c.nx; ++x) p[y] += fluid.velocity(x, y, z)[0] / (c.nx * c.nz);
    }
    return p;
  };
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> now = profile();
  const long max_steps = 200000;
  double change = 1;
  while (change > 1e-10 * u_max && fluid.step_count() < max_steps) {
    fluid.run(500);
    const std::vector<double> next = profile();
    change = 0;
    for (int y = 0; y < c.ny; ++y) change = std::max(change, std::abs(next[y] - now[y]));
    now = next;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::printf("lbsolid fluid demo: Poiseuille channel on %s (%s), %d x %d%s nodes, omega %.2f\n",
              L::name, opt.precision.c_str(), c.nx, c.ny, L::D == 3 ? " x 4" : "", c.omega);
  std::printf("body force g = %.4e per node, walls half-way at y = %.3f and %.3f\n", g, y0, y1);
  std::printf("steady after %ld steps (%.2f s)\n\n", fluid.step_count(), seconds);
  std::printf("%5s %10s %14s %14s %10s\n", "row", "y", "u_x (LB)", "u_x (exact)", "rel. err");
  double num = 0, den = 0;
  for (int y = 0; y < c.ny; ++y) {
    const double yy = y * L::row_spacing;
    const double exact = g / (2 * nu) * (yy - y0) * (y1 - yy);
    num += (now[y] - exact) * (now[y] - exact);
    den += exact * exact;
    std::printf("%5d %10.4f %14.8f %14.8f %10.2e\n", y, yy, now[y], exact, (now[y] - exact) / exact);
  }
  std::printf("\nrelative L2 error against the parabola: %.3e\n", std::sqrt(num / den));
  return fluid.step_count() < max_steps ? 0 : 1;
}

int usage(const char* message) {
  std::fprintf(stderr, "%s\nusage: lbsolid-channel-demo [--lattice D2Q9|D2Q7|D3Q19] "
                       "[--precision double|float] [--width N]\n", message);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (k + 1 >= argc) return usage(("missing value after " + arg).c_str());
    const std::string value = argv[++k];
    if (arg == "--lattice") opt.lattice = value;
    else if (arg == "--precision") opt.precision = value;
    else if (arg == "--width") opt.width = std::atoi(value.c_str());
    else return usage(("unknown option " + arg).c_str());
  }
  if (opt.width < 3 || opt.width > 4096) return usage("--width: must be between 3 and 4096");
  const bool dbl = opt.precision == "double";
  if (!dbl && opt.precision != "float") return usage("--precision: must be double or float");
  if (opt.lattice == "D2Q9") return dbl ? run<lattice::D2Q9, double>(opt) : run<lattice::D2Q9, float>(opt);
  if (opt.lattice == "D2Q7") return dbl ? run<lattice::D2Q7, double>(opt) : run<lattice::D2Q7, float>(opt);
  if (opt.lattice == "D3Q19") return dbl ? run<lattice::D3Q19, double>(opt) : run<lattice::D3Q19, float>(opt);
  return usage("--lattice: must be D2Q9, D2Q7 or D3Q19");
}
