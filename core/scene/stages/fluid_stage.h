#pragma once
// The fluid's step, then (with bodies) the momentum each coupled node gained in the exchange,
// added to its post-collision populations (MODEL.md eq. 12); or, where CouplingState::in_step,
// the step with the exchange's read and injection at each node inside it.
#include <string>
#include <vector>

#include "fluid/fluid_lattice.h"
#include "parallel/thread_pool.h"
#include "scene/stages/coupling_state.h"
#include "scene/step_stage.h"

namespace lbsolid::scene {

template <class L, class T>
class FluidStage final : public StepStage {
 public:
  // `coupling` is null without bodies.
  FluidStage(fluid::FluidLattice<L, T>& fluid, CouplingState* coupling, parallel::ThreadPool& pool)
      : fluid_(fluid), coupling_(coupling), pool_(pool) {}

  std::vector<std::string> names() const override { return {"fluid"}; }

  void run(StageClock& clock) override {
    if (coupling_ && coupling_->in_step) {  // the exchange's read and injection inside the step
      coupling_->exchange.step_fluid(fluid_);
      clock.lap(Stage::kFluid);
      return;
    }
    fluid_.step();
    clock.lap(Stage::kFluid);
    if (!coupling_) return;
    // Each node's populations sit in slots no other node writes (the in-place rules are
    // involutions, FluidLattice::check_in_place_slots), so the nodes take their momentum in parts.
    coupling_->exchange.inject(fluid_, &pool_);
    clock.lap(Stage::kInject);
  }

 private:
  fluid::FluidLattice<L, T>& fluid_;
  CouplingState* coupling_;
  parallel::ThreadPool& pool_;
};

}  // namespace lbsolid::scene
