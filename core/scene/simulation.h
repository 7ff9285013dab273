#pragma once
// A running scene. build_simulation() assembles it from ONLY the stages the scene needs (MODEL.md
// section 3's step order, minus what is absent):
//   exchange  (fluid and bodies)   pre-collision fluid moments and solid momenta at each particle's
//                                  nearest node -> the momentum each particle gives its node
//   fluid     (a fluid)            collide + stream + walls, then each node's exchange (eq. 12)
//   loads     (a body with a load) the applied force on every particle of that body
//   contact   (bodies and walls)   the wall force on particles about to cross a wall
//   fracture  (a breaking body)    links past their threshold break, first in the step
//   solid     (bodies)             the LB wave update (eqs. 6-7) with all those forces
// A stage that is absent has no storage and costs nothing. Observers are computed on request.
#include <memory>
#include <string>
#include <vector>

#include "fluid/fluid_lattice.h"
#include "scene/body_state.h"
#include "scene/instability_error.h"
#include "scene/scene.h"
#include "scene/stage_clock.h"
#include "solid/solid_system.h"

namespace lbsolid::scene {

using Vec3 = fluid::Vec3;

struct Totals {
  double fluid_mass = 0;
  Vec3 fluid_momentum{0, 0, 0};      // sum over nodes of sum_i f_i c_i
  double fluid_kinetic_energy = 0;   // sum over nodes of rho |u|^2 / 2
  Vec3 solid_momentum{0, 0, 0};      // sum of Psi
  Vec3 shed_momentum{0, 0, 0};       // what shed particles held (fracture: SolidSystem::shed)
  double solid_energy = 0;           // sum of E = sum_k |f_k|^2 (eq. 9)
  Vec3 momentum() const {
    Vec3 total;
    for (int a = 0; a < 3; ++a) total[a] = fluid_momentum[a] + solid_momentum[a] + shed_momentum[a];
    return total;
  }
};

// Everything a Simulation changes as it runs. With the scene it was built from, it is a complete
// checkpoint: load_state() into a simulation built from the same scene continues bit for bit.
struct SimulationState {
  long step = 0;
  bool has_fluid = false;
  fluid::FluidRawState fluid;  // empty without fluid
  bool has_solid = false;
  solid::SolidState solid;     // empty without bodies
};

// Density and velocity at every node, x fastest, then y, then z (C order [z][y][x]).
struct FluidFields {
  std::array<int, 3> shape{0, 0, 0};  // nx, ny, nz
  std::vector<double> density;        // one per node
  std::vector<double> velocity;       // three per node: u_x, u_y, u_z
};

class Simulation {
 public:
  virtual ~Simulation() = default;

  // One step of the pipeline; with scene().monitor.interval > 0, every that many steps the monitor
  // checks the state and throws InstabilityError ("step N: <problem>") if it left the safe region.
  virtual void step() = 0;
  void run(long steps) {
    for (long s = 0; s < steps; ++s) step();
  }
  virtual long step_count() const = 0;
  // Benchmarks: with timing on, each step adds the wall time of its stages (stage_clock.h); turning
  // it on or off clears the sums. Results do not depend on it.
  virtual void time_stages(bool on) = 0;
  virtual StageClock::Seconds stage_seconds() const = 0;
  virtual const Scene& scene() const = 0;
  // The stages run each step, in order: a subset of exchange, fluid, loads, contact, solid.
  virtual std::vector<std::string> stages() const = 0;
  virtual std::size_t fluid_bytes() const = 0;     // 0 without fluid
  virtual std::size_t solid_bytes() const = 0;     // solid and exchange storage; 0 without bodies
  virtual const solid::SolidSystem* solid() const = 0;  // null without bodies
  virtual bool has_fluid() const = 0;

  // Observers (require a fluid where they read it; std::logic_error otherwise).
  virtual std::vector<double> velocity_profile() const = 0;  // u_x(y), averaged along x (and z)
  virtual fluid::Moments fluid_moments(int x, int y, int z = 0) const = 0;
  virtual Vec3 fluid_velocity_at_particle(int p) const = 0;  // at its nearest node, before exchange
  virtual Totals totals() const = 0;
  BodyState body_state(int body) const;
  // Mean over the body's particles of |u_s - u_f| / |u_s| (u_f at the nearest node).
  double body_slip(int body) const;
  // Per particle: u_s = Psi / M.
  Vec3 particle_velocity(int p) const;
  FluidFields fluid_fields() const {  // requires a fluid
    FluidFields fields;
    fill_fluid_fields(fields);
    return fields;
  }
  // The same into `fields`, whose vectors keep their memory when they have the size already (a
  // reader that reuses one buffer then touches no fresh pages).
  virtual void fill_fluid_fields(FluidFields& fields) const = 0;
  // Density and velocity of `count` nodes from node `first` on, in fluid_fields()' order, into
  // density[count] and velocity[3 count] (either may be null): a part of the fields without a
  // copy of the whole (std::out_of_range outside the grid).
  virtual void fluid_moments_range(long first, long count, double* density, double* velocity) const = 0;

  virtual SimulationState save_state() const = 0;
  // Throws std::invalid_argument naming what does not match this simulation's scene.
  virtual void load_state(const SimulationState& state) = 0;

 protected:
  // BodyState::torque of `body` whose state is now `now` (stages/torque_record.h).
  virtual Vec3 last_torque(int body, const BodyState& now) const = 0;
  // BodyState::anchor_force of `body` (stages/anchor_record.h).
  virtual Vec3 last_anchor_force(int body) const = 0;
};

// Throws std::invalid_argument listing every problem (validate_scene) if the scene cannot run.
// Each step's fluid rows and per-particle stages (nearest node, forces, solid update) are cut into
// scene.fluid.threads parts, run on `pool` (sharing its threads with whatever else uses it) or,
// without one, on scene.fluid.threads - 1 threads of the simulation's own. Results do not depend
// on either.
std::unique_ptr<Simulation> build_simulation(const Scene& scene,
                                             std::shared_ptr<parallel::ThreadPool> pool = nullptr);

}  // namespace lbsolid::scene
