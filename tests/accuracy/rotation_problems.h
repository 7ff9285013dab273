#pragma once
// The accuracy report's rotating-body problems (accuracy_problems.h lists them), built on
// rotation_in_shear.h. Both in plane Couette flow on D2Q9 at the report's omega, in diffusive
// scaling (a fixed Reynolds number, the shear rate falling as 1 / size^2), bodies with `rotation`:
//   shear_rotation: a disk of radius R (lattice units; R / spacing particles) in a box H = L = 12 R
//     (R / H as in tests/physics/rotation_shear_test.cpp), Re = gamma_dot R^2 / nu = 0.04; the
//     Couette flow settles for 7 H^2 / (pi^2 nu) steps (its slowest mode then e^-7), then the rate
//     is taken over one radian of turn;
//   jeffery: the lattice ellipse of semi-axes 3b x b in H = 32 b, L = 64 b (body length / H = 0.19,
//     as tests/physics/jeffery_orbit_test.cpp), Re = gamma_dot a^2 / nu = 0.1, followed over its
//     first full turn after crossing the flow.
#include <string>
#include <vector>

#include "accuracy/accuracy_problems.h"

namespace lbsolid::accuracy {

RunResult run_shear_rotation(const Method& method, int radius, const RunSettings& settings);
RunResult run_jeffery(const Method& method, int semi_minor, const RunSettings& settings);

// D2Q9 x every operator that runs x particle spacing 1 and 1/2, in double (a rotation problem's
// velocities are far above float's round-off, and its cost is the fluid's at either precision).
std::vector<Method> rotation_methods(const RunSettings& settings, std::vector<std::string>* skipped);

}  // namespace lbsolid::accuracy
