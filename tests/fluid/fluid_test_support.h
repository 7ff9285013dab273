#pragma once
// Shared set-ups for the fluid tests: channel configurations, profiles and fits.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "fluid/fluid_config.h"
#include "fluid/fluid_lattice.h"
#include "fluid/kernel_isa.h"
#include "lattice/d2q7.h"
#include "lattice/d2q9.h"
#include "lattice/d3q19.h"
#include "observe/fits.h"
#include "observe/velocity_profile.h"

namespace lbsolid::testing {

using fluid::FluidConfig;
using fluid::FluidLattice;
using fluid::Vec3;
using fluid::WallKind;
using lattice::D2Q7;
using lattice::D2Q9;
using lattice::D3Q19;

// Kinematic viscosity of BGK: (1/omega - 1/2) c_s^2.
template <class L>
double bgk_viscosity(double omega) {
  return (1.0 / omega - 0.5) * L::cs2;
}

// A channel periodic in x (and z in 3D) between two y walls of the given kinds, `width` rows.
template <class L>
FluidConfig channel_config(int width, WallKind low, WallKind high, double omega = 1.0) {
  FluidConfig c;
  c.nx = 4;
  c.ny = width;
  c.nz = L::D == 3 ? 2 : 1;
  c.omega = omega;
  c.sides[fluid::kYLow].kind = low;
  c.sides[fluid::kYHigh].kind = high;
  return c;
}

using observe::velocity_profile;  // u_x(y), averaged along x and z

// Steps until the profile changes by less than `tolerance` (max abs) over `interval` steps.
template <class F>
std::vector<double> run_to_steady_profile(F& fluid, double tolerance, long max_steps,
                                          long interval = 500) {
  std::vector<double> previous = velocity_profile(fluid);
  for (long done = 0; done < max_steps; done += interval) {
    fluid.run(interval);
    std::vector<double> now = velocity_profile(fluid);
    double change = 0;
    for (std::size_t k = 0; k < now.size(); ++k) change = std::max(change, std::abs(now[k] - previous[k]));
    previous = now;
    if (change < tolerance) break;
  }
  return previous;
}

// Prints a measured figure beside its bound, so a passing run still shows how close it came.
inline void report(const std::string& what, double measured, double bound) {
  std::printf("[ figure   ] %s = %.3e (bound %.1e)\n", what.c_str(), measured, bound);
}

inline double relative_l2(const std::vector<double>& got, const std::vector<double>& want) {
  double num = 0, den = 0;
  for (std::size_t k = 0; k < got.size(); ++k) {
    num += (got[k] - want[k]) * (got[k] - want[k]);
    den += want[k] * want[k];
  }
  return std::sqrt(num / den);
}

// Every population of every node, x fastest: what the tests that hold two runs to each other bit
// for bit compare.
template <class Fluid>
std::vector<double> every_population(const Fluid& fluid) {
  const FluidConfig& c = fluid.config();
  std::vector<double> all;
  for (int z = 0; z < c.nz; ++z)
    for (int y = 0; y < c.ny; ++y)
      for (int x = 0; x < c.nx; ++x)
        for (double f : fluid.populations(x, y, z)) all.push_back(f);
  return all;
}

// Line fits come from the core's observers, as the service will use them.
using observe::fit_line;

// Limits the kernels' instruction set for a test, and restores the best path after it.
class KernelIsaLimit {
 public:
  explicit KernelIsaLimit(fluid::KernelIsa most) { fluid::limit_kernel_isa(most); }
  ~KernelIsaLimit() { fluid::limit_kernel_isa(fluid::KernelIsa::kAvx512); }
};

}  // namespace lbsolid::testing
