#pragma once
// The torque each body received in the last step (issue 16): sum_p (r_p - c) x F_p about the
// body's centre of mass c at the step's start, with r_p and F_p (its load, the exchange's
// reaction -dP, wall contact) as the solid's step reached particle p. The solid stage records the
// terms per particle; they are summed per body in index order, so the figure does not depend on
// the thread count. c is recovered from the state after the step: a step moves the body's
// mass-weighted centre by (P_before + F/2) / M and its momentum by F (eq. 8), so
// c_before = c_after - (P_after - F/2) / M.
#include <vector>

#include "parallel/thread_pool.h"
#include "scene/body_state.h"
#include "solid/solid_system.h"

namespace lbsolid::scene {

class TorqueRecord {
 public:
  TorqueRecord(int particles, int bodies) : terms_(static_cast<std::size_t>(particles) * 6), moment_(bodies), force_(bodies) {}

  // Particle p, at r, receives f this step (from any thread: each p has its own entries).
  void record(int p, const Vec3& r, const Vec3& f) {
    double* t = &terms_[static_cast<std::size_t>(p) * 6];
    t[0] = f[0];
    t[1] = f[1];
    t[2] = f[2];
    t[3] = r[1] * f[2] - r[2] * f[1];
    t[4] = r[2] * f[0] - r[0] * f[2];
    t[5] = r[0] * f[1] - r[1] * f[0];
  }
  // After the step: each body's total force and moment about the origin, bodies in parts.
  void sum(const solid::SolidSystem& solid, parallel::ThreadPool* pool, int parts) {
    const auto sum_bodies = [&](long first, long end) {
      for (long b = first; b < end; ++b) {
        const auto& body = solid.body(static_cast<int>(b));
        Vec3 force{0, 0, 0}, moment{0, 0, 0};
        for (int p = body.first; p < body.first + body.count; ++p) {
          const double* t = &terms_[static_cast<std::size_t>(p) * 6];
          for (int a = 0; a < 3; ++a) {
            force[a] += t[a];
            moment[a] += t[3 + a];
          }
        }
        force_[b] = force;
        moment_[b] = moment;
      }
    };
    if (pool && parts > 1 && solid.body_count() > 1) pool->parallel_for(solid.body_count(), parts, sum_bodies);
    else sum_bodies(0, solid.body_count());
    stepped_ = true;
  }
  std::size_t bytes_allocated() const {
    return terms_.capacity() * sizeof(double) + (moment_.capacity() + force_.capacity()) * sizeof(Vec3);
  }
  // Body b's torque about its centre of mass at the last step's start, given its state now;
  // zero before any step (also right after a restore: the record is not part of the state).
  Vec3 torque(int b, const BodyState& now) const {
    if (!stepped_) return {0, 0, 0};
    const Vec3& f = force_[b];
    Vec3 c;
    for (int a = 0; a < 3; ++a) c[a] = now.centre_of_mass[a] - (now.mass * now.velocity[a] - 0.5 * f[a]) / now.mass;
    const Vec3& m = moment_[b];
    return {m[0] - (c[1] * f[2] - c[2] * f[1]), m[1] - (c[2] * f[0] - c[0] * f[2]), m[2] - (c[0] * f[1] - c[1] * f[0])};
  }

 private:
  std::vector<double> terms_;  // per particle: F (3), then r x F (3)
  std::vector<Vec3> moment_;   // per body: sum of r x F about the origin
  std::vector<Vec3> force_;    // per body: sum of F
  bool stepped_ = false;
};

}  // namespace lbsolid::scene
