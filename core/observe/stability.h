#pragma once
// The stability monitor: looks at a running simulation for the signs that it has left the region
// where the lattice-Boltzmann model holds (non-finite values, a density outside a band around
// rho0, a Mach number |u| / c_s above a limit) and says where, so a run can stop with a clear
// message instead of carrying NaN forward. The daemon calls it between steps; a Scene's `monitor`
// makes the Simulation call it itself (scene/instability_error.h).
#include <string>
#include <vector>

#include "observe/stability_limits.h"
#include "parallel/thread_pool.h"
#include "scene/simulation.h"

namespace lbsolid::observe {

// Empty when every value is finite, every density inside the band and every Mach number within
// the limit; otherwise one problem, "<quantity> <value> at <place>". In order of precedence:
//   "non-finite density at node (x, y, z)" / "non-finite velocity at node (x, y, z)"
//   "density -0.01 (must stay positive) at node (x, y, z)"           (the lowest density)
//   "density 2.3 outside [0.5, 2] at node (x, y, z)"                 (the density furthest out)
//   "Mach number 0.62 (limit 0.5) at node (x, y, z)"                 (the fastest node)
//   "non-finite position of particle 7 of body disk" / "non-finite momentum of ..."
// The band's ends are shown as densities: limits.min_density and max_density times rho0.
// With a pool, the fluid's nodes are scanned in `parts` ranges on it; the answer is the same.
std::string find_instability(const scene::Simulation& simulation, const StabilityLimits& limits,
                             parallel::ThreadPool* pool = nullptr, int parts = 1);

}  // namespace lbsolid::observe
