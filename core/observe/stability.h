#pragma once
// The stability monitor: looks at a running simulation for the signs that it has left the region
// where the lattice-Boltzmann model holds (non-finite values, a density that is not positive, a
// Mach number |u| / c_s above a limit) and says where, so a run can stop with a clear message
// instead of carrying NaN forward.
#include <string>

#include "scene/simulation.h"

namespace lbsolid::observe {

struct StabilityLimits {
  double max_mach = 0.5;  // largest |u| / c_s allowed anywhere in the fluid
};

// Empty when every value is finite, every density positive and every Mach number within the limit;
// otherwise the first problem found: "<quantity> <value> at <place>" (e.g. "Mach number 0.62
// (limit 0.5) at node (12, 3, 0)", "non-finite position of particle 7 of body disk").
std::string find_instability(const scene::Simulation& simulation, const StabilityLimits& limits);

}  // namespace lbsolid::observe
