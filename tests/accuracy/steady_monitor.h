#pragma once
// When has a run reached its steady state? A run that relaxes to a steady state approaches it
// geometrically: sampled every `interval` steps, the change between samples shrinks by a constant
// factor q per sample, and the distance still to go is change * q / (1 - q) (the tail of that
// geometric series, Aitken's estimate). The monitor stops a run when that estimated distance,
// relative to the quantity's scale, is below the tolerance; or when the change stops shrinking
// after it has fallen far below its largest value (a round-off floor, as in float runs, or the
// residual flicker of a body crossing grid cells): going on would not change the answer.
#include <algorithm>
#include <cmath>
#include <vector>

namespace lbsolid::accuracy {

class SteadyMonitor {
 public:
  SteadyMonitor(double tolerance, double scale) : tolerance_(tolerance), scale_(scale) {}

  // Feeds the next sample; true when the run may stop.
  bool update(const std::vector<double>& now) {
    if (last_.empty()) {
      last_ = now;
      return false;
    }
    double change = 0;
    for (std::size_t k = 0; k < now.size(); ++k) change = std::max(change, std::abs(now[k] - last_[k]));
    change /= scale_;
    last_ = now;
    largest_ = std::max(largest_, change);
    const double previous = change_;
    change_ = change;
    // No change at all: the state is a fixed point of the arithmetic. In double that is the steady
    // state; in float it can be a stall short of it (increments below half an ulp are lost), so it
    // counts as a floor: the answer then carries the round-off error, as it should.
    if (change == 0) return floor_ = true;
    if (previous < 0) return false;
    const double q = change / previous;
    if (q < 0.95) {
      flat_ = 0;
      remaining_ = change * q / (1.0 - q);
      return converged_ = remaining_ < tolerance_;
    }
    // Not shrinking. Early on that is the spin-up; far below the largest change it is a floor.
    if (change < kFloorFraction * largest_ && ++flat_ >= 3) return floor_ = true;
    return false;
  }

  bool converged() const { return converged_; }  // the estimated distance fell below tolerance
  bool at_floor() const { return floor_; }         // stopped on a plateau of the change, or a stall
  double last_change() const { return change_; }   // relative to the scale

 private:
  static constexpr double kFloorFraction = 1e-3;
  double tolerance_, scale_;
  std::vector<double> last_;
  double change_ = -1, largest_ = 0, remaining_ = INFINITY;
  int flat_ = 0;
  bool converged_ = false, floor_ = false;
};

}  // namespace lbsolid::accuracy
