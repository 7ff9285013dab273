#pragma once
// A scene: everything one simulation is made of, as plain data (DESIGN.md "Data flow"). The
// builder (scene/simulation.h) turns it into a Simulation holding only the stages it needs.
#include <string>
#include <vector>

#include "coupling/momentum_exchange.h"
#include "fluid/fluid_config.h"
#include "observe/stability_limits.h"
#include "solid/body_shape.h"

namespace lbsolid::scene {

enum class LatticeKind { kD2Q9, kD2Q7, kD3Q19 };
enum class Precision { kDouble, kFloat };

const char* lattice_kind_name(LatticeKind lattice);
int lattice_dimension(LatticeKind lattice);

struct ContactSpec {
  bool enabled = true;      // bodies stop at non-periodic sides (when the scene has both)
  double restitution = 1.0;  // e in [0, 1]; 1 is exactly elastic
};

// The stability monitor a Simulation runs on itself (observe/stability.h): every `interval` steps
// it looks for non-finite values, a density outside the band and a Mach number above the limit,
// and step() throws InstabilityError (scene/instability_error.h) naming the step, the quantity and
// the place. 0 turns it off (the default: the daemon runs its own check between steps). A check
// reads every node (about as much as one fluid step), so an interval of 10 or more keeps it cheap.
struct MonitorSpec {
  int interval = 0;
  observe::StabilityLimits limits;
};

struct Scene {
  LatticeKind lattice = LatticeKind::kD2Q9;
  Precision precision = Precision::kDouble;  // of the fluid; the solid is always double
  // The grid, its sides, omega, rho0, body force, threads and streaming. Without a fluid only the
  // grid size and the sides are used: they are the box the bodies live in.
  fluid::FluidConfig fluid;
  bool with_fluid = true;
  std::vector<solid::BodySpec> bodies;
  ContactSpec contact;
  coupling::ExchangeRule exchange = coupling::ExchangeRule::kCommonVelocity;
  MonitorSpec monitor;
};

// The name body b goes by in output: its own, or "body<b>".
std::string body_name(const Scene& scene, std::size_t b);

// Every problem with the scene, each "<field>: <reason>". Empty when it can run.
std::vector<std::string> validate_scene(const Scene& scene);

// Parameters that can run but sit near the edge of the stable region, each "<field>: <reason>":
//   "omega: 1.97 is above 1.95; the fluid is close to its stability limit"
//   "bodies[0].velocity: initial Mach number 0.12 is above 0.1"
//   "sides.y_high.wall_velocity: Mach number 0.12 is above 0.1"
// Empty for a comfortable scene. Meant for a scene validate_scene() accepts.
std::vector<std::string> scene_warnings(const Scene& scene);

// Body b's solid-to-fluid mass ratio per node: the body's mass (sum of M_l = K_l/2) over the number
// of distinct fluid nodes its particles are nearest to at the start, over fluid.rho0. A bulk sheet at
// spacing 1 gives 2 / rho0; packing s particles per node multiplies it by s.
double body_mass_ratio(const Scene& scene, std::size_t b);

// A lattice's constants, from its descriptor (lattice/d2q9.h, d2q7.h, d3q19.h): c_s^2, and the
// distance between rows along y (1; sqrt(3)/2 on the hexagonal D2Q7).
double lattice_cs2(LatticeKind lattice);
double lattice_row_spacing(LatticeKind lattice);

// Where the walls of each side stand, in lattice units: half-way between the last node and the
// next, -1/2 and n - 1/2 along square axes; the D2Q7 y sides likewise, with rows sqrt(3)/2 apart.
// The D2Q7 x sides stand at -1/4 and nx - 1/4: odd rows are shifted right by half a cell, so the
// wall is a zig-zag whose slanted links are cut there (a flow along y sees them there, less
// 1/(16 nx) from the zig-zag: tests/fluid/d2q7_x_walls_test.cpp). Wall contact and body placement
// use these positions.
double wall_position(const Scene& scene, int side);

}  // namespace lbsolid::scene
