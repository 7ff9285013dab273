#pragma once
// A scene: everything one simulation is made of, as plain data (DESIGN.md "Data flow"). The
// builder (scene/simulation.h) turns it into a Simulation holding only the stages it needs.
#include <string>
#include <vector>

#include "coupling/momentum_exchange.h"
#include "fluid/fluid_config.h"
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
};

// The name body b goes by in output: its own, or "body<b>".
std::string body_name(const Scene& scene, std::size_t b);

// Every problem with the scene, each "<field>: <reason>". Empty when it can run.
std::vector<std::string> validate_scene(const Scene& scene);

// Where the walls of each side stand, in lattice units (half-way between the last node and the
// next: -1/2 and n - 1/2 along square axes; D2Q7 rows are sqrt(3)/2 apart).
double wall_position(const Scene& scene, int side);

}  // namespace lbsolid::scene
