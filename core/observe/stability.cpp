#include "observe/stability.h"

#include <cmath>
#include <sstream>

namespace lbsolid::observe {

namespace {

double sound_speed_squared(scene::LatticeKind lattice) {
  return lattice == scene::LatticeKind::kD2Q7 ? 0.25 : 1.0 / 3.0;
}

bool finite(const fluid::Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

std::string node_name(long cell, const std::array<int, 3>& shape) {
  const long nx = shape[0], ny = shape[1];
  std::ostringstream out;
  out << "node (" << cell % nx << ", " << (cell / nx) % ny << ", " << cell / (nx * ny) << ")";
  return out.str();
}

std::string check_fluid(const scene::Simulation& simulation, const StabilityLimits& limits) {
  const auto fields = simulation.fluid_fields();
  const double cs = std::sqrt(sound_speed_squared(simulation.scene().lattice));
  long worst = -1;
  double worst_mach = 0;
  for (std::size_t c = 0; c < fields.density.size(); ++c) {
    const double rho = fields.density[c];
    const fluid::Vec3 u{fields.velocity[3 * c], fields.velocity[3 * c + 1], fields.velocity[3 * c + 2]};
    std::ostringstream out;
    if (!std::isfinite(rho) || !finite(u)) {
      out << "non-finite " << (std::isfinite(rho) ? "velocity" : "density") << " at "
          << node_name(static_cast<long>(c), fields.shape);
      return out.str();
    }
    if (rho <= 0) {
      out << "density " << rho << " (must stay positive) at " << node_name(static_cast<long>(c), fields.shape);
      return out.str();
    }
    const double mach = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) / cs;
    if (mach > worst_mach) {
      worst_mach = mach;
      worst = static_cast<long>(c);
    }
  }
  if (worst_mach > limits.max_mach) {
    std::ostringstream out;
    out << "Mach number " << worst_mach << " (limit " << limits.max_mach << ") at " << node_name(worst, fields.shape);
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
