#pragma once
// The limits of the stability monitor (observe/stability.h), as plain data so that a Scene can
// carry them (scene/scene.h) without depending on the Simulation the monitor reads.
namespace lbsolid::observe {

struct StabilityLimits {
  double max_mach = 0.5;  // largest |u| / c_s allowed anywhere in the fluid
  // The density band, as multiples of the scene's reference density fluid.rho0: a band relative
  // to rho0 holds for any solid-to-fluid mass ratio (which is varied through rho0, MODEL.md
  // section 2). LB density deviates from rho0 by about Mach^2, so a node at half or twice rho0 is
  // far outside the weakly compressible regime the model describes. min_density = 0 keeps only
  // the check that the density stays positive; max_density = infinity drops the upper bound.
  double min_density = 0.5;
  double max_density = 2.0;
};

}  // namespace lbsolid::observe
