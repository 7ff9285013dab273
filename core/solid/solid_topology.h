#pragma once
// The solid's link topology (MODEL.md section 2): square in 2D with links c_1..c_4 = +x, +y, -x, -y,
// cubic in 3D with +x, +y, +z, -x, -y, -z. Link k and link k + D are opposite, so opp(k) is the
// paper's "i + 2" in 2D.
#include <array>

namespace lbsolid::solid {

using Vec3 = std::array<double, 3>;
using Label = std::array<int, 3>;
using Rotation = std::array<std::array<double, 3>, 3>;  // rows
using Quaternion = std::array<double, 4>;              // w, x, y, z: a unit quaternion, w >= 0

struct SolidTopology {
  int dimension;  // 2 or 3

  int links() const { return 2 * dimension; }
  int opposite(int k) const { return (k + dimension) % links(); }
  // The label offset of link k.
  Label link(int k) const {
    Label c{0, 0, 0};
    c[k % dimension] = k < dimension ? 1 : -1;
    return c;
  }
};

}  // namespace lbsolid::solid
