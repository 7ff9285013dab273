#pragma once
// The drag of a periodic array of bodies (one disk or ball of particles in a fully periodic box)
// against the Stokes-flow references of Sangani & Acrivos / Hasimoto, run to its steady state.
// Shared by tests/physics/periodic_array_drag_test.cpp (whose header explains the references, the
// superficial velocity U and the radii) and the accuracy report's coupled problems
// (array_drag_2d, array_drag_3d: run_array_drag below).
//
// Radii of a body of N particles at spacing s (all in lattice units):
//   a_cells = s sqrt(N / pi) (2D), s cbrt(3 N / (4 pi)) (3D): the disk (ball) with the area
//             (volume) of the particles' own cells, s^d each: the body as built, within 3% of the
//             radius asked for (BodySpec radius x spacing) at R = 3 and 1.5% from R = 4;
//   a_w     = the wet-node radius: the surface through the outermost coupled NODES, i.e. the
//             radius of the disk (ball) with the area (volume) of the distinct nodes the particles
//             couple to, minus half a lattice spacing. At s = 1 on D2Q9 / D3Q19 (body centred on
//             a node) every particle has its own node and a_w = a_cells - 1/2 exactly; on D2Q7
//             (particles off the triangular grid) the test's convention a_cells - 1/2 is kept.
//   a_h     = the hydrodynamic radius: the radius for which the reference gives the measured drag.
#include <string>

#include "accuracy/accuracy_problems.h"
#include "scene/scene.h"
#include "solid/body_shape.h"

namespace lbsolid::accuracy {

// Sangani & Acrivos (1982), square array of cylinders: F / (mu U), F per unit length, U superficial.
double square_array_drag(double phi);
// Sangani & Acrivos (1982), simple cubic array of spheres: K in F = 6 pi mu a U K, U superficial.
double cubic_array_k(double phi);
// The reference's F / (mu U) for bodies of radius a, one per cell of the given area (2D) or volume.
double reference_drag(int dimension, double a, double cell);
double solid_fraction(int dimension, double a, double cell);
// The radius for which the reference gives `drag` (it grows with a over the range searched). With
// `interstitial`, the radius it would give if the measured U were the interstitial mean velocity
// U / (1 - phi) instead of the superficial one (for contrast only).
double hydrodynamic_radius(int dimension, double drag, double cell, bool interstitial = false);
// Radius of the disk (ball) with the area (volume) of N unit cells.
double cell_radius(int dimension, double particles);
// The no-slip surface through the outermost coupled nodes at spacing 1: half a spacing inside the cells.
double wet_node_radius(int dimension, double particles);

struct ArrayBox {
  scene::LatticeKind lattice = scene::LatticeKind::kD2Q9;
  int nx = 0, ny = 0, nz = 1;
};
int dimension_of(const ArrayBox& box);
// Area (2D) or volume of the box in lattice units. A D2Q7 node covers sqrt(3)/2.
double cell_measure(const ArrayBox& box);

// The fluid and the stopping rule of a run. The defaults are the physics test's: the paper's fluid
// (omega = 1, rho0 = 1), BGK in double, a load set for U ~ 2e-6 (Re < 1e-3), stopped when U and the
// body's velocity are estimated within 1e-5 (relative) of their steady values.
struct ArrayFluid {
  double omega = 1.0;
  double rho0 = 1.0;
  scene::Precision precision = scene::Precision::kDouble;
  fluid::CollisionModel collision = fluid::CollisionModel::kBgk;
  int threads = 1;
  double target_velocity = 2e-6;  // relative velocity the load is set for
  double tolerance = 1e-5;        // relative distance to the steady state at the stop
  long max_steps = 200000;
  // Consecutive samples that must meet the tolerance before the run stops. One is the physics
  // test's (its bodies do not move off their nodes). The report's float runs go faster (1e-4) and
  // their bodies move up to about one spacing, so some particles hop to the next node; the jump a
  // hop makes in U can look like convergence for one sample, so the report asks for two.
  int quiet_samples = 1;
};
double viscosity(const ArrayBox& box, const ArrayFluid& fluid);
// Dynamic viscosity: rho0 per node is rho0 / (node area) per unit area on D2Q7.
double dynamic_viscosity(const ArrayBox& box, const ArrayFluid& fluid);

struct SteadyRun {
  double particles = 0;
  double force = 0;        // total load on the body
  double superficial = 0;  // U = v_body - <u>_nodes, steady
  double body_velocity = 0;
  double displacement = 0;  // of the body's centre of mass over the run
  long steps = 0;
  long interval = 0;        // steps between the monitor's samples
  bool converged = false;   // the monitor's tolerance was met (not a floor, not the cap)
  std::string stop = "cap";  // "tolerance", "floor" (change stalled: round-off) or "cap"
  double seconds = 0;        // from building the simulation to the last sample
  std::size_t memory_bytes = 0;  // Simulation::fluid_bytes() + solid_bytes()
};

// Runs `body` (its load set here) in the periodic box until steady. `expected_drag` (F / (mu U))
// only sets the load's scale, so that U is near fluid.target_velocity.
SteadyRun run_to_steady(const ArrayBox& box, solid::BodySpec body, double expected_drag, const ArrayFluid& fluid = {});

struct ArrayResult {
  std::string label;
  int dimension = 2;
  double spacing = 1;
  double cell = 0;  // area or volume per body
  double nodes = 0;  // distinct nodes the particles couple to
  SteadyRun run;
  double drag = 0;  // measured F / (mu U)
  double a_cells = 0, a_wet = 0, a_hydro = 0;
  double reynolds = 0;     // 2 a_w U / nu
  double error_cells = 0;  // drag / reference(a_cells) - 1
  double error_wet = 0;    // drag / reference(a_w) - 1
  double band_low = 0, band_high = 0;  // reference(a_w -+ 1/2) / reference(a_w) - 1
};

// One body of `radius` particles at `spacing` (a disk or a ball of physical radius radius x
// spacing) in the box. At spacing 1 it is centred on the box's middle node; at spacing s < 1 its
// centre is shifted by (1 - s)/2 along each axis, so that no particle sits half-way between two
// nodes (at s = 1/2: particles at node -+ 1/4, two per node per axis).
ArrayResult periodic_array(const ArrayBox& box, double radius, const std::string& label, const ArrayFluid& fluid = {},
                           double spacing = 1.0);

// The accuracy report's coupled problems. array_drag_2d: a disk of physical radius R (lattice
// units) on D2Q9 in a square box of side round(5.6 R) (phi ~ 0.1, the physics test's shape);
// array_drag_3d: a ball of radius R on D3Q19 in a cube of side 4 R (phi ~ 0.065). The body has
// R / method.spacing particles per radius. measured = F / (mu U); error = |drag /
// reference(a_cells) - 1|, the error of the body as built; the run also carries a_w, a_h and the
// signed error against reference(a_w). The fluid: settings.omega, rho0 = 1, the method's
// precision and operator, U ~ settings.array_velocity, tolerance settings.array_tolerance.
RunResult run_array_drag(Problem problem, const Method& method, int radius, const RunSettings& settings);

// The box run_array_drag uses for radius R.
ArrayBox array_box(Problem problem, int radius);

}  // namespace lbsolid::accuracy
