#pragma once
// Rotating bodies (scene Body.rotation): after the solid's step, each one's springs turn to the
// frame that best fits its new shape (solid/solid_system.h, co-rotational springs). Timed with
// the solid's step.
#include <string>
#include <vector>

#include "scene/step_stage.h"
#include "solid/solid_system.h"

namespace lbsolid::scene {

class RotationStage final : public StepStage {
 public:
  explicit RotationStage(solid::SolidSystem& solid) : solid_(solid) {}
  std::vector<std::string> names() const override { return {"rotation"}; }
  void run(StageClock& clock) override {
    solid_.turn_frames();
    clock.lap(Stage::kSolid);
  }

 private:
  solid::SolidSystem& solid_;
};

}  // namespace lbsolid::scene
