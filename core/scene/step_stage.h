#pragma once
// One effect of a simulation step. The scene builder assembles each simulation's step as an ordered
// list of these from what its scene declares, in MODEL.md's order (stages/): the exchange, the
// fluid with the injection of what it gained, the solid with the forces the scene has, the turn of
// rotating bodies' frames. A scene runs the code of its own effects and no other;
// Simulation::stages() lists their names. (The stability monitor is not an effect: the step runs
// it after the stages, every scene.monitor.interval steps.)
#include <string>
#include <vector>

#include "scene/stage_clock.h"

namespace lbsolid::scene {

class StepStage {
 public:
  virtual ~StepStage() = default;
  // What Simulation::stages() lists for this stage, in order.
  virtual std::vector<std::string> names() const = 0;
  // Runs the stage; `clock` is lapped at the end of each part it times.
  virtual void run(StageClock& clock) = 0;
};

}  // namespace lbsolid::scene
