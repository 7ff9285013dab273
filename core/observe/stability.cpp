#include "observe/stability.h"

#include <algorithm>
#include <cmath>
#include <vector>
#include <sstream>

namespace lbsolid::observe {

namespace {

bool finite(const fluid::Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

std::string node_name(long cell, const std::array<int, 3>& shape) {
  const long nx = shape[0], ny = shape[1];
  std::ostringstream out;
  out << "node (" << cell % nx << ", " << (cell / nx) % ny << ", " << cell / (nx * ny) << ")";
  return out.str();
}

std::string check_fluid(const scene::Simulation& simulation, const StabilityLimits& limits) {
  const auto& c = simulation.scene().fluid;
  const std::array<int, 3> shape{c.nx, c.ny, c.nz};
  const long cells = static_cast<long>(c.nx) * c.ny * c.nz;
  const double cs = std::sqrt(scene::lattice_cs2(simulation.scene().lattice));
  const double rho0 = c.rho0;
  const double low = limits.min_density * rho0, high = limits.max_density * rho0;
  // One pass over blocks of nodes (never a copy of the whole field): a non-finite value ends it at
  // once; the extremes of density and Mach are kept, so the message names the worst node rather
  // than the first one past a limit.
  constexpr long kBlock = 4096;
  std::vector<double> density(kBlock), velocity(3 * kBlock);
  long lowest = -1, highest = -1, fastest = -1;
  double rho_min = 0, rho_max = 0, worst_mach = 0;
  for (long first = 0; first < cells; first += kBlock) {
    const long count = std::min(kBlock, cells - first);
    simulation.fluid_moments_range(first, count, density.data(), velocity.data());
    for (long k = 0; k < count; ++k) {
      const long cell = first + k;
      const double rho = density[k];
      const fluid::Vec3 u{velocity[3 * k], velocity[3 * k + 1], velocity[3 * k + 2]};
      if (!std::isfinite(rho) || !finite(u)) {
        std::ostringstream out;
        out << "non-finite " << (std::isfinite(rho) ? "velocity" : "density") << " at " << node_name(cell, shape);
        return out.str();
      }
      if (lowest < 0 || rho < rho_min) lowest = cell, rho_min = rho;
      if (highest < 0 || rho > rho_max) highest = cell, rho_max = rho;
      const double mach = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) / cs;
      if (mach > worst_mach) {
        worst_mach = mach;
        fastest = cell;
      }
    }
  }
  if (lowest < 0) return {};
  std::ostringstream out;
  if (rho_min <= 0) {
    out << "density " << rho_min << " (must stay positive) at " << node_name(lowest, shape);
    return out.str();
  }
  const double below = rho_min < low ? low / rho_min : 1.0, above = rho_max > high ? rho_max / high : 1.0;
  if (below > 1.0 || above > 1.0) {
    const bool low_side = below >= above;
    out << "density " << (low_side ? rho_min : rho_max) << " outside [" << low << ", " << high << "] at "
        << node_name(low_side ? lowest : highest, shape);
    return out.str();
  }
  if (worst_mach > limits.max_mach) {
    out << "Mach number " << worst_mach << " (limit " << limits.max_mach << ") at " << node_name(fastest, shape);
    return out.str();
  }
  return {};
}

std::string check_solid(const solid::SolidSystem& solid) {
  for (int p = 0; p < solid.particle_count(); ++p) {
    const bool position_ok = finite(solid.position(p));
    if (position_ok && finite(solid.momentum(p))) continue;
    const auto& body = solid.body(solid.body_of(p));
    std::ostringstream out;
    out << "non-finite " << (position_ok ? "momentum" : "position") << " of particle " << p - body.first
        << " of body " << body.name;
    return out.str();
  }
  return {};
}

}  // namespace

std::string find_instability(const scene::Simulation& simulation, const StabilityLimits& limits) {
  if (simulation.has_fluid()) {
    auto problem = check_fluid(simulation, limits);
    if (!problem.empty()) return problem;
  }
  if (simulation.solid()) return check_solid(*simulation.solid());
  return {};
}

}  // namespace lbsolid::observe
