#pragma once
// The solid's step (MODEL.md eqs. 6-7) with the forces the scene has: the bodies' loads, the
// exchange's reaction -dP, then wall contact, which needs every other force. Each force is summed
// as the solid's step reaches its particle, in one pass; which forces exist is fixed when the
// stage is built (make_solid_stage), so a scene runs no code for a force it lacks. With a torque
// record (scenes with a rotating body), each particle's total force is recorded as well; with an
// anchor record (scenes with anchors), an anchored particle gets the force that holds it, -2 Psi,
// and the record what its anchor absorbed (anchor_record.h). With particle forces (point loads,
// fracture impulses: particle_forces.h), each particle's are added to its body's load.
#include <memory>
#include <string>
#include <vector>

#include "parallel/thread_pool.h"
#include "scene/scene.h"
#include "scene/stages/anchor_record.h"
#include "scene/stages/coupling_state.h"
#include "scene/stages/particle_forces.h"
#include "scene/stages/torque_record.h"
#include "scene/step_stage.h"
#include "solid/wall_contact.h"

namespace lbsolid::scene {

// The records a solid stage may write or read, null where the scene has none.
struct SolidStageRecords {
  CouplingState* coupling = nullptr;        // the exchange's, with a fluid
  TorqueRecord* torque = nullptr;           // with a rotating body
  AnchorRecord* anchors = nullptr;          // with an anchor
  const ParticleForces* forces = nullptr;   // with point loads or fracture
};

template <int D, bool kLoads, bool kExchange, bool kContact, bool kTorque, bool kAnchors, bool kParticleForces>
class SolidStage final : public StepStage {
 public:
  SolidStage(const Scene& scene, solid::SolidSystem& solid, const SolidStageRecords& records,
             const solid::ContactWalls& walls, parallel::ThreadPool& pool)
      : scene_(scene), solid_(solid), coupling_(records.coupling), walls_(walls), torque_(records.torque),
        anchors_(records.anchors), forces_(records.forces), pool_(pool) {}

  std::vector<std::string> names() const override {
    std::vector<std::string> n;
    if (kLoads) n.push_back("loads");
    if (kContact) n.push_back("contact");
    n.push_back("solid");
    return n;
  }

  void run(StageClock& clock) override {
    const solid::ParticleVectors momenta = solid_.momenta();
    const auto force = [&](int p) {
      solid::Vec3 f = kLoads ? solid_.body(solid_.body_of(p)).load : solid::Vec3{0, 0, 0};
      if constexpr (kParticleForces) forces_->add_to(p, f);
      if constexpr (kAnchors) {
        if (solid_.anchored(p)) {  // held: the anchor takes whatever else acts on it
          if constexpr (kExchange) {
            const solid::Vec3 dp = coupling_->exchange.anchor_dp(p);
            for (int a = 0; a < 3; ++a) f[a] -= dp[a];
          }
          const solid::Vec3 psi = momenta.get<D>(p);
          anchors_->record(p, {2 * psi[0] + f[0], 2 * psi[1] + f[1], 2 * psi[2] + f[2]});
          return solid::Vec3{-2 * psi[0], -2 * psi[1], -2 * psi[2]};
        }
      }
      if constexpr (kExchange) {
        const solid::Vec3 compared = coupling_->rotating
                                         ? solid::ParticleVectors{coupling_->momenta_at_nodes.data(), D}.get<D>(p)
                                         : momenta.get<D>(p);
        coupling_->exchange.template prefetch_particle_dp<D>(p + kDpAhead);
        const solid::Vec3 dp = coupling_->exchange.template particle_dp<D>(p, compared, solid_.mass(p));
        for (int a = 0; a < 3; ++a) f[a] -= dp[a];
      }
      if constexpr (kContact) solid::add_wall_contact<D>(walls_, solid_, p, f);
      if constexpr (kTorque) torque_->record(p, solid_.position(p), f);
      return f;
    };
    if constexpr (kExchange) {
      if (!coupling_->rotating) {  // the next exchange's nodes found here (coupling_state.h)
        coupling_->exchange.begin_locate(solid_.particle_count());
        solid_.stream(force, NextNodes{*coupling_, solid_.positions().data}, &pool_, scene_.fluid.threads);
        coupling_->located_version = solid_.positions_version();
      } else {
        solid_.stream(force, &pool_, scene_.fluid.threads);
      }
    } else {
      solid_.stream(force, &pool_, scene_.fluid.threads);
    }
    if constexpr (kTorque) torque_->sum(solid_, &pool_, scene_.fluid.threads);
    clock.lap(Stage::kSolid);
  }

 private:
  static constexpr long kDpAhead = 16;  // particles
  const Scene& scene_;
  solid::SolidSystem& solid_;
  CouplingState* coupling_;
  const solid::ContactWalls& walls_;
  TorqueRecord* torque_;
  AnchorRecord* anchors_;
  const ParticleForces* forces_;
  parallel::ThreadPool& pool_;
};

// The solid stage for the forces present: loads, the exchange (records.coupling not null),
// contact, particle forces (records.forces); recording the torques when records.torque is not null,
// holding the anchors when records.anchors is not null.
template <int D>
std::unique_ptr<StepStage> make_solid_stage(bool loads, bool contact, const Scene& scene, solid::SolidSystem& solid,
                                            const SolidStageRecords& records, const solid::ContactWalls& walls,
                                            parallel::ThreadPool& pool) {
  auto make = [&]<bool kLoads, bool kExchange, bool kContact, bool kForces>() -> std::unique_ptr<StepStage> {
    if (records.torque)  // rotating bodies are never anchored (validate_body_spec)
      return std::make_unique<SolidStage<D, kLoads, kExchange, kContact, true, false, kForces>>(scene, solid, records,
                                                                                                walls, pool);
    if (records.anchors)
      return std::make_unique<SolidStage<D, kLoads, kExchange, kContact, false, true, kForces>>(scene, solid, records,
                                                                                                walls, pool);
    return std::make_unique<SolidStage<D, kLoads, kExchange, kContact, false, false, kForces>>(scene, solid, records,
                                                                                               walls, pool);
  };
  auto with_forces = [&]<bool kLoads, bool kExchange, bool kContact>() {
    return records.forces ? make.template operator()<kLoads, kExchange, kContact, true>()
                          : make.template operator()<kLoads, kExchange, kContact, false>();
  };
  auto with_contact = [&]<bool kLoads, bool kExchange>() {
    return contact ? with_forces.template operator()<kLoads, kExchange, true>()
                   : with_forces.template operator()<kLoads, kExchange, false>();
  };
  auto with_exchange = [&]<bool kLoads>() {
    return records.coupling ? with_contact.template operator()<kLoads, true>()
                            : with_contact.template operator()<kLoads, false>();
  };
  return loads ? with_exchange.template operator()<true>() : with_exchange.template operator()<false>();
}

}  // namespace lbsolid::scene
