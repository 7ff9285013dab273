#pragma once
// Wall time spent in each stage of a simulation step, for benchmarks (what a coupled step costs,
// stage by stage). Off by default, when a lap costs one branch; on, two clock reads a stage.
// Stages that run in parts on a pool are timed from the stepping thread, start to last part.
#include <array>
#include <chrono>

namespace lbsolid::scene {

// locate: each particle's nearest node; exchange: the momentum exchange, reading the fluid;
// fluid: the fluid's step; inject: the exchanged momentum into the fluid; solid: the solid's step
// with the forces on each particle (loads, the exchange's reaction, wall contact) summed as it
// goes; monitor: the stability check. Without rotating bodies the solid's step finds the next
// step's nodes as it moves the particles, in its own time: locate is then near zero after the
// first step (coupling_state.h).
enum class Stage { kLocate, kExchange, kFluid, kInject, kSolid, kMonitor };
inline constexpr int kStageCount = 6;

inline const char* stage_name(Stage stage) {
  constexpr const char* kNames[kStageCount] = {"locate", "exchange", "fluid", "inject", "solid", "monitor"};
  return kNames[static_cast<int>(stage)];
}

class StageClock {
 public:
  using Seconds = std::array<double, kStageCount>;

  void enable(bool on) {
    on_ = on;
    seconds_.fill(0);
  }
  bool enabled() const { return on_; }
  // Marks the start of a step.
  void start() {
    if (on_) last_ = std::chrono::steady_clock::now();
  }
  // The time since the last mark goes to `stage`.
  void lap(Stage stage) {
    if (!on_) return;
    const auto now = std::chrono::steady_clock::now();
    seconds_[static_cast<int>(stage)] += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }
  const Seconds& seconds() const { return seconds_; }

 private:
  bool on_ = false;
  std::chrono::steady_clock::time_point last_;
  Seconds seconds_{};
};

}  // namespace lbsolid::scene
