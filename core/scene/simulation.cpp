#include "scene/simulation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "coupling/node_locator.h"
#include "lattice/d2q7.h"
#include "lattice/d2q9.h"
#include "lattice/d3q19.h"
#include "observe/stability.h"
#include "observe/velocity_profile.h"
#include "scene/stages/exchange_stage.h"
#include "scene/stages/fracture_stage.h"
#include "scene/stages/fluid_stage.h"
#include "scene/stages/rotation_stage.h"
#include "scene/stages/solid_stage.h"
#include "scene/stages/anchor_record.h"
#include "scene/stages/particle_forces.h"
#include "scene/stages/torque_record.h"
#include "solid/wall_contact.h"

namespace lbsolid::scene {

namespace {

bool nonzero(const Vec3& v) { return v[0] != 0 || v[1] != 0 || v[2] != 0; }

template <class L, class T>
class SimulationImpl final : public Simulation {
 public:
  SimulationImpl(const Scene& scene, std::shared_ptr<parallel::ThreadPool> pool)
      : scene_(scene),
        locator_(scene.fluid),
        pool_(pool ? std::move(pool) : std::make_shared<parallel::ThreadPool>(scene.fluid.threads)) {
    // The populations' layout is the fluid's own choice where the scene leaves it open
    // (FluidLattice::chosen_layout), bodies or not: since 1d14dbc the pairwise rule's batched
    // calls cost little more in blocks than in arrays, and the blocks' faster step wins
    // (docs/performance.md).
    if (scene.with_fluid) fluid_ = std::make_unique<fluid::FluidLattice<L, T>>(scene.fluid, pool_);
    bool loads = false, rotating = false, point_loads = false, fracture = false;
    if (!scene.bodies.empty()) {
      solid_ = std::make_unique<solid::SolidSystem>(L::D);
      for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
        const auto& spec = scene.bodies[b];
        const std::vector<solid::Label> labels = solid::body_labels(spec, L::D);
        const int body = solid_->add_body(body_name(scene, b), labels, spec.spacing, spec.centre, spec.velocity,
                                          spec.load, spec.angular_velocity, spec.rotation);
        for (std::size_t q = 0; q < labels.size(); ++q)
          if (solid::is_anchored(spec, labels[q])) solid_->anchor(solid_->body(body).first + static_cast<int>(q));
        loads = loads || nonzero(spec.load);
        rotating = rotating || spec.rotation;
        point_loads = point_loads || !spec.point_loads.empty();
        fracture = fracture || spec.fracture.enabled();
      }
      if (point_loads || fracture) {
        forces_ = std::make_unique<ParticleForces>(solid_->particle_count(), point_loads, fracture);
        for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
          if (scene.bodies[b].point_loads.empty()) continue;
          const auto& body = solid_->body(static_cast<int>(b));
          std::map<solid::Label, int> particle_of;  // validate_body_spec checked every label is one
          for (int p = body.first; p < body.first + body.count; ++p) particle_of.emplace(solid_->label(p), p);
          for (const auto& point : scene.bodies[b].point_loads)
            forces_->add_point_load(particle_of.at(point.label), point.force);
        }
      }
      if (fluid_) {
        coupling_ = std::make_unique<CouplingState>(scene, solid_->particle_count(), rotating);
        coupling_->in_step =
            fluid_->can_exchange_in_step() && coupling_->exchange.rule() == coupling::ExchangeRule::kCommonVelocity;
        coupling_->nearest_cells = [&locator = locator_](const double* positions, long first, long end,
                                                        coupling::CellIndex* cells) {
          locator.nearest_cells(positions, first, end, cells);
        };
      }
      if (rotating) torque_ = std::make_unique<TorqueRecord>(solid_->particle_count(), solid_->body_count());
      if (solid_->any_anchored()) anchors_ = std::make_unique<AnchorRecord>(solid_->particle_count());
      if (scene.contact.enabled) {
        walls_.restitution = scene.contact.restitution;
        for (int side = 0; side < 2 * L::D; ++side) {
          walls_.present[side] = scene.fluid.sides[side].kind != fluid::WallKind::kPeriodic;
          walls_.position[side] = wall_position(scene, side);
        }
      }
    }
    // The step: only the stages the scene calls for, in MODEL.md's order (step_stage.h).
    if (fracture) stages_.push_back(std::make_unique<FractureStage>(scene_, *solid_, *forces_, steps_, *pool_));
    if (coupling_)
      stages_.push_back(
          std::make_unique<ExchangeStage<L, T>>(scene_, locator_, *fluid_, *solid_, *coupling_, *pool_));
    if (fluid_) stages_.push_back(std::make_unique<FluidStage<L, T>>(*fluid_, coupling_.get(), *pool_));
    if (solid_)
      stages_.push_back(
          make_solid_stage<L::D>(loads || point_loads, walls_.any(), scene_, *solid_,
                                 {coupling_.get(), torque_.get(), anchors_.get(), forces_.get()}, walls_, *pool_));
    if (rotating) stages_.push_back(std::make_unique<RotationStage>(scene_, *solid_, *pool_));  // after the solid's update
  }

  void step() override {
    clock_.start();
    for (const auto& stage : stages_) stage->run(clock_);
    ++steps_;
    // After the step is complete, so a throw leaves a consistent state at step N to read or save.
    const int every = scene_.monitor.interval;
    if (every > 0 && steps_ % every == 0) {
      const std::string problem =
          observe::find_instability(*this, scene_.monitor.limits, pool_.get(), scene_.fluid.threads);
      clock_.lap(Stage::kMonitor);
      if (!problem.empty()) throw InstabilityError(steps_, problem);
    }
  }

  long step_count() const override { return steps_; }
  void time_stages(bool on) override { clock_.enable(on); }
  StageClock::Seconds stage_seconds() const override { return clock_.seconds(); }
  const Scene& scene() const override { return scene_; }
  bool has_fluid() const override { return fluid_ != nullptr; }
  const solid::SolidSystem* solid() const override { return solid_.get(); }
  Vec3 last_torque(int body, const BodyState& now) const override {
    return torque_ ? torque_->torque(body, now) : Vec3{0, 0, 0};
  }
  Vec3 last_anchor_force(int body) const override {
    return anchors_ ? anchors_->body_force(*solid_, body) : Vec3{0, 0, 0};
  }

  std::vector<std::string> stages() const override {
    std::vector<std::string> names;
    for (const auto& stage : stages_)
      for (auto& name : stage->names()) names.push_back(std::move(name));
    return names;
  }

  std::size_t fluid_bytes() const override { return fluid_ ? fluid_->bytes_allocated() : 0; }
  std::size_t solid_bytes() const override {
    if (!solid_) return 0;
    return solid_->bytes_allocated() + (coupling_ ? coupling_->bytes_allocated() : 0) +
           (torque_ ? torque_->bytes_allocated() : 0) + (anchors_ ? anchors_->bytes_allocated() : 0) +
           (forces_ ? forces_->bytes_allocated() : 0);
  }

  std::vector<double> velocity_profile() const override {
    return observe::velocity_profile(require_fluid("velocity_profile"));
  }

  fluid::Moments fluid_moments(int x, int y, int z) const override {
    return require_fluid("fluid_moments").moments(x, y, z);
  }

  Vec3 fluid_velocity_at_particle(int p) const override {
    const auto& f = require_fluid("fluid_velocity_at_particle");
    if (!solid_) throw std::logic_error("fluid_velocity_at_particle: the scene has no bodies");
    const auto node = locator_.nearest(solid_->position(p));
    return f.velocity(node[0], node[1], node[2]);
  }

  Totals totals() const override {
    Totals t;
    if (fluid_) {
      t.fluid_mass = fluid_->total_mass();
      t.fluid_momentum = fluid_->total_momentum();
      const auto& c = scene_.fluid;
      for (int z = 0; z < c.nz; ++z)
        for (int y = 0; y < c.ny; ++y)
          for (int x = 0; x < c.nx; ++x) {
            const auto m = fluid_->moments(x, y, z);
            t.fluid_kinetic_energy += 0.5 * m.rho * (m.u[0] * m.u[0] + m.u[1] * m.u[1] + m.u[2] * m.u[2]);
          }
    }
    if (solid_) {
      t.solid_momentum = solid_->total_momentum();
      t.shed_momentum = solid_->total_shed_momentum();
      t.solid_energy = solid_->total_energy();
    }
    return t;
  }

  void fill_fluid_fields(FluidFields& fields) const override {
    const auto& f = require_fluid("fluid_fields");
    const auto& c = scene_.fluid;
    fields.shape = {c.nx, c.ny, c.nz};
    fields.density.resize(f.cells());
    fields.velocity.resize(3 * f.cells());
    // Every thread of the pool takes rows (a whole field is read while the session waits, and
    // each node's moments depend on that node alone, so the parts cannot change a value).
    const long rows = static_cast<long>(c.ny) * c.nz;
    pool_->parallel_for(rows, [&](long first_row, long end_row) {
      const long first = first_row * c.nx;
      fluid_moments_range(first, (end_row - first_row) * c.nx, fields.density.data() + first,
                          fields.velocity.data() + 3 * first);
    });
  }

  void fluid_moments_range(long first, long count, double* density, double* velocity) const override {
    const auto& f = require_fluid("fluid_moments_range");
    const auto& c = scene_.fluid;
    if (first < 0 || count < 0 || count > f.cells() - first)
      throw std::out_of_range("fluid_moments_range: cells [" + std::to_string(first) + ", +" + std::to_string(count) +
                              ") outside the " + std::to_string(f.cells()) + " nodes");
    // Row by row: each row's segment in [first, first + count) at once.
    for (long k = 0; k < count;) {
      const long cell = first + k;
      const int x = static_cast<int>(cell % c.nx);
      const long row = cell / c.nx;
      const int n = static_cast<int>(std::min<long>(c.nx - x, count - k));
      f.row_moments(static_cast<int>(row % c.ny), static_cast<int>(row / c.ny), x, n, density ? density + k : nullptr,
                    velocity ? velocity + 3 * k : nullptr);
      k += n;
    }
  }

  SimulationState save_state() const override {
    SimulationState state;
    state.step = steps_;
    state.has_fluid = fluid_ != nullptr;
    if (fluid_) state.fluid = fluid_->raw_state();
    state.has_solid = solid_ != nullptr;
    if (solid_) state.solid = solid_->state();
    return state;
  }

  void load_state(const SimulationState& state) override {
    if (state.has_fluid != (fluid_ != nullptr))
      throw std::invalid_argument(std::string("state: ") + (state.has_fluid ? "has" : "has no") +
                                  " fluid but the scene " + (fluid_ ? "has one" : "has none"));
    if (state.has_solid != (solid_ != nullptr))
      throw std::invalid_argument(std::string("state: ") + (state.has_solid ? "has" : "has no") +
                                  " bodies but the scene " + (solid_ ? "has some" : "has none"));
    if (state.step < 0) throw std::invalid_argument("state.step: must not be negative");
    if (fluid_) fluid_->restore_raw_state(state.fluid);
    if (solid_) solid_->restore(state.solid);
    steps_ = state.step;
  }

 private:
  const fluid::FluidLattice<L, T>& require_fluid(const char* what) const {
    if (!fluid_) throw std::logic_error(std::string(what) + ": the scene has no fluid");
    return *fluid_;
  }

  Scene scene_;
  coupling::NodeLocator<L> locator_;
  // Runs the fluid's rows and the per-particle stages (nearest node, forces, solid update) in
  // scene_.fluid.threads parts: a daemon's shared pool, or one of the simulation's own.
  std::shared_ptr<parallel::ThreadPool> pool_;
  std::unique_ptr<fluid::FluidLattice<L, T>> fluid_;
  std::unique_ptr<solid::SolidSystem> solid_;
  std::unique_ptr<CouplingState> coupling_;  // with fluid and bodies
  std::unique_ptr<TorqueRecord> torque_;     // with a rotating body
  std::unique_ptr<AnchorRecord> anchors_;    // with an anchored particle
  std::unique_ptr<ParticleForces> forces_;   // with point loads or a breaking body
  solid::ContactWalls walls_;
  std::vector<std::unique_ptr<StepStage>> stages_;
  long steps_ = 0;
  StageClock clock_;
};

template <class L>
std::unique_ptr<Simulation> build_for_lattice(const Scene& scene, std::shared_ptr<parallel::ThreadPool> pool) {
  if (scene.precision == Precision::kFloat) return std::make_unique<SimulationImpl<L, float>>(scene, std::move(pool));
  return std::make_unique<SimulationImpl<L, double>>(scene, std::move(pool));
}

}  // namespace

std::unique_ptr<Simulation> build_simulation(const Scene& scene, std::shared_ptr<parallel::ThreadPool> pool) {
  const auto errors = validate_scene(scene);
  if (!errors.empty()) {
    std::string message = "invalid scene: ";
    for (std::size_t k = 0; k < errors.size(); ++k) message += (k ? "; " : "") + errors[k];
    throw std::invalid_argument(message);
  }
  switch (scene.lattice) {
    case LatticeKind::kD2Q9: return build_for_lattice<lattice::D2Q9>(scene, std::move(pool));
    case LatticeKind::kD2Q7: return build_for_lattice<lattice::D2Q7>(scene, std::move(pool));
    case LatticeKind::kD3Q19: return build_for_lattice<lattice::D3Q19>(scene, std::move(pool));
  }
  throw std::invalid_argument("lattice: unknown lattice");
}

BodyState Simulation::body_state(int body) const {
  const auto* s = solid();
  if (!s || body < 0 || body >= s->body_count())
    throw std::out_of_range("body: no body " + std::to_string(body) + " in this scene");
  BodyState state = measure_body(*s, body);
  state.torque = last_torque(body, state);
  state.anchor_force = last_anchor_force(body);
  return state;
}

Vec3 Simulation::particle_velocity(int p) const {
  const auto* s = solid();
  if (!s) throw std::logic_error("particle_velocity: the scene has no bodies");
  if (p < 0 || p >= s->particle_count())
    throw std::out_of_range("particle_velocity: no particle " + std::to_string(p) + " (the scene has " +
                            std::to_string(s->particle_count()) + ")");
  const Vec3 psi = s->momentum(p);
  const double m = s->mass(p);
  if (m == 0) return {0, 0, 0};  // shed: it no longer moves
  return {psi[0] / m, psi[1] / m, psi[2] / m};
}

double Simulation::body_slip(int body) const {
  const auto* s = solid();
  if (!s || body < 0 || body >= s->body_count())
    throw std::out_of_range("body: no body " + std::to_string(body) + " in this scene");
  const auto& b = s->body(body);
  double sum = 0;
  int counted = 0;
  for (int p = b.first; p < b.first + b.count; ++p) {
    if (s->shed(p)) continue;  // no longer in the flow's exchange
    ++counted;
    const Vec3 us = particle_velocity(p), uf = fluid_velocity_at_particle(p);
    const double diff = std::hypot(us[0] - uf[0], us[1] - uf[1], us[2] - uf[2]);
    sum += diff / std::hypot(us[0], us[1], us[2]);
  }
  return counted ? sum / counted : 0;
}

}  // namespace lbsolid::scene
