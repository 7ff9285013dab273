#pragma once
// The exchange (MODEL.md section 3): each particle's nearest node (unless the last solid step
// found them: CouplingState::located_version), then the momentum exchange against the nodes'
// pre-collision fluid, in the simulation's parts (its fluid's part inside the fluid's step where
// that is done: CouplingState::in_step).
#include <cmath>
#include <string>
#include <vector>

#include "fluid/fluid_lattice.h"
#include "parallel/thread_pool.h"
#include "scene/body_state.h"
#include "scene/stages/coupling_state.h"
#include "scene/step_stage.h"

namespace lbsolid::scene {

template <class L, class T>
class ExchangeStage final : public StepStage {
 public:
  ExchangeStage(const Scene& scene, const coupling::NodeLocator<L>& locator, const fluid::FluidLattice<L, T>& fluid,
                const solid::SolidSystem& solid, CouplingState& coupling, parallel::ThreadPool& pool)
      : scene_(scene), locator_(locator), fluid_(fluid), solid_(solid), coupling_(coupling), pool_(pool) {}

  std::vector<std::string> names() const override { return {"exchange"}; }

  void run(StageClock& clock) override {
    const int parts = scene_.fluid.threads;
    const solid::ParticleVectors positions = solid_.positions();
    if (coupling_.rotating) {  // the nodes themselves are kept, for momenta_at_nodes()
      coupling_.exchange.locate(
          solid_.particle_count(),
          [&](long p) {
            const coupling::Node node = locator_.nearest(positions.get<L::D>(p));
            coupling_.node[p] = node;
            return static_cast<coupling::CellIndex>(locator_.cell(node));
          },
          &pool_, parts);
    } else if (coupling_.located_version != solid_.positions_version()) {  // not found in the solid's step
      coupling_.exchange.locate_ranges(
          solid_.particle_count(),
          [&](long first, long end, coupling::CellIndex* cells) {
            locator_.nearest_cells(positions.data, first, end, cells);
          },
          &pool_, parts);
    }
    clock.lap(Stage::kLocate);
    const solid::ParticleVectors momenta = coupling_.rotating ? momenta_at_nodes() : solid_.momenta();
    const std::vector<char>* anchored = solid_.any_anchored() ? &solid_.anchored_flags() : nullptr;
    if (coupling_.in_step)  // the fluid's read waits for its step (FluidStage)
      coupling_.exchange.compute_sums(solid_.masses(), momenta, &pool_, parts, anchored);
    else
      coupling_.exchange.compute(solid_.masses(), momenta, fluid_, &pool_, parts, anchored);
    clock.lap(Stage::kExchange);
  }

 private:
  // The momenta the exchange compares with each particle's node: a rotating body's particle moves
  // with its body's spin, so the solid at its node, |node - r| up to half a spacing away, moves at
  // u + w x (node - r). Comparing the node's fluid with u alone would make a fluid that turns with
  // the body rub against it (a torque that grows with the body and falls with viscosity: measured,
  // a disk in shear turned at 0.4-0.9 of gamma_dot / 2). Only the comparison changes: the
  // momentum each exchange gives the fluid is still taken from the particle.
  solid::ParticleVectors momenta_at_nodes() {
    const solid::ParticleVectors momenta = solid_.momenta();
    auto& at_nodes = coupling_.momenta_at_nodes;
    at_nodes.assign(momenta.data, momenta.data + static_cast<std::size_t>(solid_.particle_count()) * L::D);
    const double period[3] = {static_cast<double>(scene_.fluid.nx), scene_.fluid.ny * L::row_spacing,
                              static_cast<double>(scene_.fluid.nz)};
    // Each body adds its spin to its own particles' entries only: bodies in parts.
    const auto add_spin = [&](long first_body, long end_body) {
      for (int b = static_cast<int>(first_body); b < end_body; ++b) {
        const auto& body = solid_.body(b);
        if (!body.rotates) continue;
        const Vec3 w = measure_body(solid_, b, /*with_orientation=*/false).angular_velocity;
        for (int p = body.first; p < body.first + body.count; ++p) {
          const auto& node = coupling_.node[p];
          const Vec3 at = fluid::FluidLattice<L, T>::position(node[0], node[1], node[2]);
          const Vec3 r = solid_.position(p);
          Vec3 d{0, 0, 0};
          for (int a = 0; a < L::D; ++a) {
            d[a] = at[a] - r[a];
            d[a] -= period[a] * std::round(d[a] / period[a]);  // the node across a periodic side
          }
          const double m = solid_.mass(p);
          double* at_node = &at_nodes[static_cast<std::size_t>(p) * L::D];
          at_node[0] += m * (w[1] * d[2] - w[2] * d[1]);
          at_node[1] += m * (w[2] * d[0] - w[0] * d[2]);
          if constexpr (L::D == 3) at_node[2] += m * (w[0] * d[1] - w[1] * d[0]);
        }
      }
    };
    const int parts = scene_.fluid.threads;
    if (parts > 1 && solid_.body_count() > 1) pool_.parallel_for(solid_.body_count(), parts, add_spin);
    else add_spin(0, solid_.body_count());
    return {at_nodes.data(), L::D};
  }

  const Scene& scene_;
  const coupling::NodeLocator<L>& locator_;
  const fluid::FluidLattice<L, T>& fluid_;
  const solid::SolidSystem& solid_;
  CouplingState& coupling_;
  parallel::ThreadPool& pool_;
};

}  // namespace lbsolid::scene
