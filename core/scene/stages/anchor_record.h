#pragma once
// What the anchors absorbed in the last step (MODEL.md section 5): an anchored particle's step
// needs a total force of -2 Psi to stay put (eqs. 6-7), so the anchor supplies -2 Psi minus the
// other forces on it (load, the exchange's reaction) and absorbs the opposite,
//   absorbed_p = 2 Psi_p + F_other,p,
// the momentum the flow and the rest of the body hand to the anchor per step: the force on it.
// Written by the solid stage, each particle its own entry (so in parts); summed per body on request.
#include <vector>

#include "solid/solid_system.h"

namespace lbsolid::scene {

class AnchorRecord {
 public:
  explicit AnchorRecord(int particles) : absorbed_(static_cast<std::size_t>(particles), solid::Vec3{0, 0, 0}) {}

  void record(int p, const solid::Vec3& absorbed) { absorbed_[p] = absorbed; }
  // Body b's anchors together, in particle order (zero for a body without anchors, and before
  // the first step).
  solid::Vec3 body_force(const solid::SolidSystem& solid, int b) const {
    solid::Vec3 sum{0, 0, 0};
    const auto& body = solid.body(b);
    for (int p = body.first; p < body.first + body.count; ++p)
      if (solid.anchored(p) && !solid.shed(p))  // a shed anchor is no longer stepped
        for (int a = 0; a < 3; ++a) sum[a] += absorbed_[p][a];
    return sum;
  }
  std::size_t bytes_allocated() const { return absorbed_.capacity() * sizeof(solid::Vec3); }

 private:
  std::vector<solid::Vec3> absorbed_;
};

}  // namespace lbsolid::scene
