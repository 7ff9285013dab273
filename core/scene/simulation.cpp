#include "scene/simulation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "coupling/momentum_exchange.h"
#include "coupling/node_locator.h"
#include "lattice/d2q7.h"
#include "lattice/d2q9.h"
#include "lattice/d3q19.h"
#include "observe/stability.h"
#include "observe/velocity_profile.h"
#include "solid/wall_contact.h"

namespace lbsolid::scene {

namespace {

// x with m x = v by Cramer's rule; zero if m is singular (to round-off of its entries' size).
Vec3 solve_3x3(const double m[3][3], const Vec3& v) {
  const auto det = [](double a, double b, double c, double d, double e, double f, double g, double h, double i) {
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  };
  const double d = det(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]);
  double scale = 0;
  for (int i = 0; i < 3; ++i) scale = std::max(scale, std::abs(m[i][i]));
  if (!(std::abs(d) > 1e-12 * scale * scale * scale)) return {0, 0, 0};
  return {det(v[0], m[0][1], m[0][2], v[1], m[1][1], m[1][2], v[2], m[2][1], m[2][2]) / d,
          det(m[0][0], v[0], m[0][2], m[1][0], v[1], m[1][2], m[2][0], v[2], m[2][2]) / d,
          det(m[0][0], m[0][1], v[0], m[1][0], m[1][1], v[1], m[2][0], m[2][1], v[2]) / d};
}

bool nonzero(const Vec3& v) { return v[0] != 0 || v[1] != 0 || v[2] != 0; }

template <class L, class T>
class SimulationImpl final : public Simulation {
 public:
  SimulationImpl(const Scene& scene, std::shared_ptr<parallel::ThreadPool> pool)
      : scene_(scene),
        locator_(scene.fluid),
        pool_(pool ? std::move(pool) : std::make_shared<parallel::ThreadPool>(scene.fluid.threads)) {
    if (scene.with_fluid) fluid_ = std::make_unique<fluid::FluidLattice<L, T>>(scene.fluid, pool_);
    if (scene.bodies.empty()) return;
    solid_ = std::make_unique<solid::SolidSystem>(L::D);
    for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
      const auto& spec = scene.bodies[b];
      solid_->add_body(body_name(scene, b), solid::body_labels(spec, L::D), spec.spacing, spec.centre, spec.velocity,
                       spec.load, spec.angular_velocity, spec.rotation);
      loads_ = loads_ || nonzero(spec.load);
      rotating_ = rotating_ || spec.rotation;
    }
    const int n = solid_->particle_count();
    if (fluid_) {
      exchange_ = std::make_unique<coupling::MomentumExchange>(
          std::array<int, 3>{scene.fluid.nx, scene.fluid.ny, scene.fluid.nz}, scene.exchange);
      if (rotating_) node_.resize(n);
    }
    if (scene.contact.enabled) {
      walls_.restitution = scene.contact.restitution;
      for (int side = 0; side < 2 * L::D; ++side) {
        walls_.present[side] = scene.fluid.sides[side].kind != fluid::WallKind::kPeriodic;
        walls_.position[side] = wall_position(scene, side);
      }
    }
  }

  void step() override {
    const int parts = scene_.fluid.threads;
    clock_.start();
    if (exchange_) {
      const solid::ParticleVectors positions = solid_->positions();
      exchange_->locate(
          solid_->particle_count(),
          [&](long p) {
            const coupling::Node node = locator_.nearest(positions.get<L::D>(p));
            if (rotating_) node_[p] = node;  // for momenta_at_nodes()
            return static_cast<coupling::CellIndex>(locator_.cell(node));
          },
          pool_.get(), parts);
      clock_.lap(Stage::kLocate);
      exchange_->compute(solid_->masses(), rotating_ ? momenta_at_nodes() : solid_->momenta(), *fluid_, pool_.get(),
                         parts);
      clock_.lap(Stage::kExchange);
    }
    if (fluid_) {
      fluid_->step();
      clock_.lap(Stage::kFluid);
      // Each node's populations sit in slots no other node writes (the in-place rules are
      // involutions, FluidLattice::check_in_place_slots), so the nodes take their momentum in parts.
      if (exchange_) {
        exchange_->inject(*fluid_, pool_.get());
        clock_.lap(Stage::kInject);
      }
    }
    if (solid_) {
      // The forces on each particle (loads, the exchange's reaction, then wall contact, which needs
      // every other force) are summed as the solid's step reaches it.
      const solid::ParticleVectors momenta = solid_->momenta();
      const auto force = [&](int p) {
        Vec3 f = loads_ ? solid_->body(solid_->body_of(p)).load : Vec3{0, 0, 0};
        if (exchange_) {
          const Vec3 dp = exchange_->particle_dp(
              p, rotating_ ? solid::ParticleVectors{momenta_at_nodes_.data(), L::D}.get<L::D>(p) : momenta.get<L::D>(p),
              solid_->mass(p));
          for (int a = 0; a < 3; ++a) f[a] -= dp[a];
        }
        if (walls_.any()) solid::add_wall_contact(walls_, *solid_, p, f);
        return f;
      };
      solid_->step(force, pool_.get(), parts);
      clock_.lap(Stage::kSolid);
    }
    ++steps_;
    // After the step is complete, so a throw leaves a consistent state at step N to read or save.
    const int every = scene_.monitor.interval;
    if (every > 0 && steps_ % every == 0) {
      const std::string problem = observe::find_instability(*this, scene_.monitor.limits);
      clock_.lap(Stage::kMonitor);
      if (!problem.empty()) throw InstabilityError(steps_, problem);
    }
  }

  // The momenta the exchange compares with each particle's node: a rotating body's particle moves
  // with its body's spin, so the solid at its node, |node - r| up to half a spacing away, moves at
  // u + w x (node - r). Comparing the node's fluid with u alone would make a fluid that turns with
  // the body rub against it (a torque that grows with the body and falls with viscosity: measured,
  // a disk in shear turned at 0.4-0.9 of gamma_dot / 2). Only the comparison changes: the
  // momentum each exchange gives the fluid is still taken from the particle.
  solid::ParticleVectors momenta_at_nodes() {
    const solid::ParticleVectors momenta = solid_->momenta();
    momenta_at_nodes_.assign(momenta.data, momenta.data + static_cast<std::size_t>(solid_->particle_count()) * L::D);
    const double period[3] = {static_cast<double>(scene_.fluid.nx), scene_.fluid.ny * L::row_spacing,
                              static_cast<double>(scene_.fluid.nz)};
    for (int b = 0; b < solid_->body_count(); ++b) {
      const auto& body = solid_->body(b);
      if (!body.rotates) continue;
      const Vec3 w = body_state(b).angular_velocity;
      for (int p = body.first; p < body.first + body.count; ++p) {
        const auto& node = node_[p];
        const Vec3 at = fluid::FluidLattice<L, T>::position(node[0], node[1], node[2]);
        Vec3 d{0, 0, 0};
        for (int a = 0; a < L::D; ++a) {
          d[a] = at[a] - solid_->position(p)[a];
          d[a] -= period[a] * std::round(d[a] / period[a]);  // the node across a periodic side
        }
        const double m = solid_->mass(p);
        double* at_node = &momenta_at_nodes_[static_cast<std::size_t>(p) * L::D];
        at_node[0] += m * (w[1] * d[2] - w[2] * d[1]);
        at_node[1] += m * (w[2] * d[0] - w[0] * d[2]);
        if constexpr (L::D == 3) at_node[2] += m * (w[0] * d[1] - w[1] * d[0]);
      }
    }
    return {momenta_at_nodes_.data(), L::D};
  }

  long step_count() const override { return steps_; }
  void time_stages(bool on) override { clock_.enable(on); }
  StageClock::Seconds stage_seconds() const override { return clock_.seconds(); }
  const Scene& scene() const override { return scene_; }
  bool has_fluid() const override { return fluid_ != nullptr; }
  const solid::SolidSystem* solid() const override { return solid_.get(); }

  std::vector<std::string> stages() const override {
    std::vector<std::string> s;
    if (exchange_) s.push_back("exchange");
    if (fluid_) s.push_back("fluid");
    if (loads_) s.push_back("loads");
    if (solid_ && walls_.any()) s.push_back("contact");
    if (solid_) s.push_back("solid");
    if (rotating_) s.push_back("rotation");  // after the solid's update (SolidSystem::step)
    return s;
  }

  std::size_t fluid_bytes() const override { return fluid_ ? fluid_->bytes_allocated() : 0; }
  std::size_t solid_bytes() const override {
    if (!solid_) return 0;
    std::size_t bytes = solid_->bytes_allocated();
    if (exchange_)
      bytes += exchange_->bytes_allocated() + node_.capacity() * sizeof(coupling::Node) +
               momenta_at_nodes_.capacity() * sizeof(double);
    return bytes;
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
  std::unique_ptr<coupling::MomentumExchange> exchange_;
  solid::ContactWalls walls_;
  bool loads_ = false;
  bool rotating_ = false;                // some body's springs turn with it
  std::vector<double> momenta_at_nodes_; // momenta_at_nodes()' answer, kept between steps
  long steps_ = 0;
  std::vector<coupling::Node> node_;  // rotating scenes: each particle's node, from the last locate
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
  BodyState state;
  const auto& b = s->body(body);
  Vec3 momentum{0, 0, 0};
  for (int p = b.first; p < b.first + b.count; ++p) {
    const double m = s->mass(p);
    const Vec3 psi = s->momentum(p);
    state.mass += m;
    for (int a = 0; a < 3; ++a) {
      state.centre_of_mass[a] += m * s->position(p)[a];
      momentum[a] += psi[a];
    }
  }
  for (int a = 0; a < 3; ++a) {
    state.centre_of_mass[a] /= state.mass;
    state.velocity[a] = momentum[a] / state.mass;
  }
  double inertia[3][3] = {};
  for (int p = b.first; p < b.first + b.count; ++p) {
    const double m = s->mass(p);
    const Vec3 psi = s->momentum(p);
    Vec3 r;
    for (int a = 0; a < 3; ++a) r[a] = s->position(p)[a] - state.centre_of_mass[a];
    state.angular_momentum[0] += r[1] * psi[2] - r[2] * psi[1];
    state.angular_momentum[1] += r[2] * psi[0] - r[0] * psi[2];
    state.angular_momentum[2] += r[0] * psi[1] - r[1] * psi[0];
    const double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) inertia[i][j] += m * ((i == j ? r2 : 0.0) - r[i] * r[j]);
  }
  if (s->dimension() == 2) {
    if (inertia[2][2] > 0) state.angular_velocity[2] = state.angular_momentum[2] / inertia[2][2];
    state.orientation = s->best_fit_angle(body);
  } else {
    state.angular_velocity = solve_3x3(inertia, state.angular_momentum);
  }
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
  return {psi[0] / m, psi[1] / m, psi[2] / m};
}

double Simulation::body_slip(int body) const {
  const auto* s = solid();
  if (!s || body < 0 || body >= s->body_count())
    throw std::out_of_range("body: no body " + std::to_string(body) + " in this scene");
  const auto& b = s->body(body);
  double sum = 0;
  for (int p = b.first; p < b.first + b.count; ++p) {
    const Vec3 us = particle_velocity(p), uf = fluid_velocity_at_particle(p);
    const double diff = std::hypot(us[0] - uf[0], us[1] - uf[1], us[2] - uf[2]);
    sum += diff / std::hypot(us[0], us[1], us[2]);
  }
  return sum / b.count;
}

}  // namespace lbsolid::scene
