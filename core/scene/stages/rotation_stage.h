#pragma once
// Rotating bodies (scene Body.rotation): after the solid's step, each one's springs turn to the
// frame that best fits its new shape (solid/solid_system.h, co-rotational springs). Timed with
// the solid's step.
#include <string>
#include <vector>

#include "parallel/thread_pool.h"
#include "scene/scene.h"
#include "scene/step_stage.h"
#include "solid/solid_system.h"

namespace lbsolid::scene {

class RotationStage final : public StepStage {
 public:
  RotationStage(const Scene& scene, solid::SolidSystem& solid, parallel::ThreadPool& pool)
      : scene_(scene), solid_(solid), pool_(pool) {}
  std::vector<std::string> names() const override { return {"rotation"}; }
  void run(StageClock& clock) override {
    solid_.turn_frames(&pool_, scene_.fluid.threads);
    clock.lap(Stage::kSolid);
  }

 private:
  const Scene& scene_;
  solid::SolidSystem& solid_;
  parallel::ThreadPool& pool_;
};

}  // namespace lbsolid::scene
