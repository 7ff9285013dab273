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

// What one range of nodes shows: its first non-finite node, else its extremes (each the first node
// where it occurs, as one pass in node order would find it).
struct FluidScan {
  long non_finite = -1;  // the first node with a non-finite value
  bool density_finite = true;  // at that node
  long lowest = -1, highest = -1, fastest = -1;
  double rho_min = 0, rho_max = 0, worst_mach = 0;

  // Folds in the scan of the range that follows this one: the result is that of one scan of both.
  void then(const FluidScan& next) {
    if (non_finite >= 0) return;
    if (next.non_finite >= 0) {
      non_finite = next.non_finite;
      density_finite = next.density_finite;
      return;
    }
    if (next.lowest >= 0 && (lowest < 0 || next.rho_min < rho_min)) lowest = next.lowest, rho_min = next.rho_min;
    if (next.highest >= 0 && (highest < 0 || next.rho_max > rho_max)) highest = next.highest, rho_max = next.rho_max;
    if (next.worst_mach > worst_mach) fastest = next.fastest, worst_mach = next.worst_mach;
  }
};

// Nodes [first, end) in blocks (never a copy of the whole field); a non-finite value ends it.
FluidScan scan_fluid(const scene::Simulation& simulation, double cs, long first, long end) {
  constexpr long kBlock = 4096;
  std::vector<double> density(kBlock), velocity(3 * kBlock);
  FluidScan scan;
  for (long block = first; block < end; block += kBlock) {
    const long count = std::min(kBlock, end - block);
    simulation.fluid_moments_range(block, count, density.data(), velocity.data());
    for (long k = 0; k < count; ++k) {
      const long cell = block + k;
      const double rho = density[k];
      const fluid::Vec3 u{velocity[3 * k], velocity[3 * k + 1], velocity[3 * k + 2]};
      if (!std::isfinite(rho) || !finite(u)) {
        scan.non_finite = cell;
        scan.density_finite = std::isfinite(rho);
        return scan;
      }
      if (scan.lowest < 0 || rho < scan.rho_min) scan.lowest = cell, scan.rho_min = rho;
      if (scan.highest < 0 || rho > scan.rho_max) scan.highest = cell, scan.rho_max = rho;
      const double mach = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) / cs;
      if (mach > scan.worst_mach) {
        scan.worst_mach = mach;
        scan.fastest = cell;
      }
    }
  }
  return scan;
}

std::string check_fluid(const scene::Simulation& simulation, const StabilityLimits& limits,
                        parallel::ThreadPool* pool, int parts) {
  const auto& c = simulation.scene().fluid;
  const std::array<int, 3> shape{c.nx, c.ny, c.nz};
  const long cells = static_cast<long>(c.nx) * c.ny * c.nz;
  const double cs = std::sqrt(scene::lattice_cs2(simulation.scene().lattice));
  const double rho0 = c.rho0;
  const double low = limits.min_density * rho0, high = limits.max_density * rho0;
  // The nodes in `parts` ranges, scanned on the pool and folded in order: the message is the one a
  // single scan would give, whatever the number of parts. The extremes name the worst node rather
  // than the first one past a limit.
  parts = pool ? std::max(1, parts) : 1;
  std::vector<FluidScan> scans(parts);
  const auto run = [&](long first_part, long end_part) {
    for (long k = first_part; k < end_part; ++k) scans[k] = scan_fluid(simulation, cs, cells * k / parts, cells * (k + 1) / parts);
  };
  if (parts > 1) pool->parallel_for(parts, parts, run);
  else run(0, 1);
  FluidScan all = scans[0];
  for (int k = 1; k < parts; ++k) all.then(scans[k]);
  std::ostringstream out;
  if (all.non_finite >= 0) {
    out << "non-finite " << (all.density_finite ? "velocity" : "density") << " at " << node_name(all.non_finite, shape);
    return out.str();
  }
  if (all.lowest < 0) return {};
  if (all.rho_min <= 0) {
    out << "density " << all.rho_min << " (must stay positive) at " << node_name(all.lowest, shape);
    return out.str();
  }
  const double below = all.rho_min < low ? low / all.rho_min : 1.0, above = all.rho_max > high ? all.rho_max / high : 1.0;
  if (below > 1.0 || above > 1.0) {
    const bool low_side = below >= above;
    out << "density " << (low_side ? all.rho_min : all.rho_max) << " outside [" << low << ", " << high << "] at "
        << node_name(low_side ? all.lowest : all.highest, shape);
    return out.str();
  }
  if (all.worst_mach > limits.max_mach) {
    out << "Mach number " << all.worst_mach << " (limit " << limits.max_mach << ") at " << node_name(all.fastest, shape);
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

std::string find_instability(const scene::Simulation& simulation, const StabilityLimits& limits,
                             parallel::ThreadPool* pool, int parts) {
  if (simulation.has_fluid()) {
    auto problem = check_fluid(simulation, limits, pool, parts);
    if (!problem.empty()) return problem;
  }
  if (simulation.solid()) return check_solid(*simulation.solid());
  return {};
}

}  // namespace lbsolid::observe
