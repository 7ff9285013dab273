#pragma once
// What Simulation::step() throws when the scene's stability monitor (Scene::monitor) finds the run
// outside the region where the model holds. what() is "step N: <problem>", with <problem> the
// monitor's message (observe::find_instability: quantity, value, place); the simulation that threw
// keeps its state at step N, so it can still be read, saved or inspected.
#include <stdexcept>
#include <string>

namespace lbsolid::scene {

class InstabilityError : public std::runtime_error {
 public:
  InstabilityError(long step, const std::string& problem)
      : std::runtime_error("step " + std::to_string(step) + ": " + problem), step_(step), problem_(problem) {}

  long step() const { return step_; }
  // The monitor's message alone, without the step.
  const std::string& message() const { return problem_; }

 private:
  long step_;
  std::string problem_;
};

}  // namespace lbsolid::scene
