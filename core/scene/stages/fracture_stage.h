#pragma once
// Fracture (issue 18, MODEL.md section 5), at the start of a step, before anything reads the
// solid: every link of a breaking body whose force or stretch is past its threshold
// (solid::FractureSpec) breaks, in particle order. Its two vectors become impulses of this step's
// solid update, each to the particle that held it (the solid stage adds them to its forces), so
// total momentum is what it was; both ends' masses drop to K/2 of the links left. A particle left
// without a link is shed (SolidSystem::shed) with what it held. The links are tested in parts, the
// breaks made in order, so the result does not depend on the parts.
#include <cmath>
#include <string>
#include <vector>

#include "parallel/thread_pool.h"
#include "scene/scene.h"
#include "scene/stages/particle_forces.h"
#include "scene/step_stage.h"
#include "solid/solid_system.h"

namespace lbsolid::scene {

class FractureStage final : public StepStage {
 public:
  // `steps`: the simulation's count of steps done, read when a link breaks.
  FractureStage(const Scene& scene, solid::SolidSystem& solid, ParticleForces& forces, const long& steps,
                parallel::ThreadPool& pool)
      : scene_(scene), solid_(solid), forces_(forces), steps_(steps), pool_(pool),
        breaking_(static_cast<std::size_t>(solid.particle_count()), 0) {}

  std::vector<std::string> names() const override { return {"fracture"}; }

  void run(StageClock& clock) override {
    forces_.clear_impulses();
    const int n = solid_.particle_count();
    const auto test = [&](long first, long end) {
      for (int p = static_cast<int>(first); p < end; ++p) breaking_[p] = links_past_threshold(p);
    };
    if (scene_.fluid.threads > 1) pool_.parallel_for(n, scene_.fluid.threads, test);
    else test(0, n);
    for (int p = 0; p < n; ++p) {
      if (!breaking_[p]) continue;
      for (int k = 0; k < solid_.dimension(); ++k)
        if (breaking_[p] & (1 << k)) break_link(p, k);
    }
    clock.lap(Stage::kSolid);
  }

 private:
  // Bit k set: p's link along +c_k (k < dimension) breaks.
  unsigned char links_past_threshold(int p) const {
    const solid::FractureSpec& rule = scene_.bodies[solid_.body_of(p)].fracture;
    if (!rule.enabled()) return 0;
    const double spacing = solid_.body(solid_.body_of(p)).spacing;
    unsigned char bits = 0;
    for (int k = 0; k < solid_.dimension(); ++k) {
      const int q = solid_.neighbour(p, k);
      if (q < 0) continue;
      const solid::Vec3 back = solid_.incoming(p, solid_.topology().opposite(k)), ahead = solid_.incoming(q, k);
      const double force = std::hypot(back[0] - ahead[0], back[1] - ahead[1], back[2] - ahead[2]);  // |e|, eq. 11
      const solid::Vec3 rp = solid_.position(p), rq = solid_.position(q);
      const double stretch = std::hypot(rq[0] - rp[0], rq[1] - rp[1], rq[2] - rp[2]) / spacing - 1;
      if ((rule.max_force > 0 && force > rule.max_force) || (rule.max_stretch > 0 && stretch > rule.max_stretch))
        bits |= static_cast<unsigned char>(1 << k);
    }
    return bits;
  }

  void break_link(int p, int k) {
    const solid::RemovedVectors removed = solid_.break_link(p, k, steps_ + 1);  // the step now running
    forces_.add_impulse(p, removed.at_particle);
    forces_.add_impulse(removed.neighbour, removed.at_neighbour);
    for (int end : {p, removed.neighbour})
      if (solid_.shed(end)) {  // no link left to move it: what it held is booked with its body
        solid_.shed(end, forces_.impulse(end));
        forces_.drop_impulse(end);
      }
  }

  const Scene& scene_;
  solid::SolidSystem& solid_;
  ParticleForces& forces_;
  const long& steps_;
  parallel::ThreadPool& pool_;
  std::vector<unsigned char> breaking_;  // per particle, this step's test
};

}  // namespace lbsolid::scene
