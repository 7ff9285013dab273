#pragma once
// Forces on single particles beyond their body's uniform load, for the solid stage: the scene's
// point loads (constant) and the fracture stage's impulses (one step only: the vectors a broken
// link held, handed back to their owners so that momentum stays exact, MODEL.md section 5). Either
// part is absent (no storage, nothing added) when the scene has none.
#include <vector>

#include "solid/solid_system.h"

namespace lbsolid::scene {

class ParticleForces {
 public:
  ParticleForces(int particles, bool point_loads, bool impulses)
      : point_(point_loads ? particles : 0, solid::Vec3{0, 0, 0}),
        impulse_(impulses ? particles : 0, solid::Vec3{0, 0, 0}) {}

  void add_point_load(int p, const solid::Vec3& f) { add(point_[p], f); }
  void add_impulse(int p, const solid::Vec3& f) {
    touched_.push_back(p);  // a particle twice is cleared twice: harmless
    add(impulse_[p], f);
  }
  const solid::Vec3& impulse(int p) const { return impulse_[p]; }
  void drop_impulse(int p) { impulse_[p] = {0, 0, 0}; }
  void clear_impulses() {
    for (int p : touched_) impulse_[p] = {0, 0, 0};
    touched_.clear();
  }

  // `force` += what acts on particle p here. A part that is present adds its exact value, zero
  // for particles it does not name.
  void add_to(int p, solid::Vec3& force) const {
    if (!point_.empty()) add(force, point_[p]);
    if (!impulse_.empty()) add(force, impulse_[p]);
  }
  std::size_t bytes_allocated() const {
    return (point_.capacity() + impulse_.capacity()) * sizeof(solid::Vec3) + touched_.capacity() * sizeof(int);
  }

 private:
  static void add(solid::Vec3& to, const solid::Vec3& f) {
    for (int a = 0; a < 3; ++a) to[a] += f[a];
  }
  std::vector<solid::Vec3> point_;
  std::vector<solid::Vec3> impulse_;
  std::vector<int> touched_;
};

}  // namespace lbsolid::scene
