#pragma once
// What a body is: a shape that yields a set of integer labels on the square/cubic topology, and
// where and how it starts. Plain data; body_labels() turns a shape into labels.
#include <string>
#include <vector>

#include "solid/solid_topology.h"

namespace lbsolid::solid {

enum class BodyShape {
  kRectangle,  // size[0] x size[1] (x size[2] in 3D) particles: a sheet or a box
  kDisk,       // every label within `radius` of the centre label: a disk, a ball in 3D
  kChain,      // `length` particles along `axis`: a 1D polymer
  kLabels,     // the explicit `labels`
};

const char* body_shape_name(BodyShape shape);

// A force on one particle of a body, added to the body's uniform load: opposite loads at the two
// ends of a chain, a row of a sheet pulled.
struct PointLoad {
  Label label;
  Vec3 force{0, 0, 0};
};

// When a body's links break (issue 18, MODEL.md section 5). A link p -> q carries the force of a
// vector spring of stiffness 1 stretched by its extension e = r_q - r_p - Delta0 (eq. 11 gives
// e = f_opp(k)(p) - f_k(q) from the link's two vectors); it breaks when |e| exceeds max_force, or
// when its stretch |r_q - r_p| / spacing - 1 exceeds max_stretch. A criterion at 0 is off; a body
// breaks when either is on.
struct FractureSpec {
  double max_force = 0;
  double max_stretch = 0;
  bool enabled() const { return max_force > 0 || max_stretch > 0; }
};

struct BodySpec {
  std::string name;  // for output; defaults to "body<index>"
  BodyShape shape = BodyShape::kRectangle;
  std::array<int, 3> size{1, 1, 1};  // kRectangle: particles per axis
  double radius = 0;                 // kDisk: in particles (rest spacings)
  int length = 0;                    // kChain: particles
  int axis = 0;                      // kChain: 0 = x, 1 = y, 2 = z
  std::vector<Label> labels;         // kLabels
  double spacing = 1.0;  // rest distance between linked particles, lattice units
  Vec3 centre{0, 0, 0};  // where the centroid of the rest shape is placed
  Vec3 velocity{0, 0, 0};  // initial rigid velocity, lattice units per step
  Vec3 load{0, 0, 0};      // external force on every particle, lattice units
  Vec3 angular_velocity{0, 0, 0};  // initial spin about the centre of mass, radians per step (2D: z)
  bool rotation = false;  // the springs' rest frame turns with the body (SolidSystem)
  // Anchored particles are held where they are placed (infinite mass) and still exchange momentum
  // with the fluid; what they absorb is the force on the anchors (MODEL.md section 5). Either the
  // whole body, or the particles of these labels (labels of the body's own shape).
  bool anchored = false;
  std::vector<Label> anchor_labels;
  std::vector<PointLoad> point_loads;  // each added to `load` on its particle
  FractureSpec fracture;
};

// Whether particle `label` of `spec` is anchored.
bool is_anchored(const BodySpec& spec, const Label& label);

// The labels of a shape, in a fixed order (x fastest). Empty if the shape's size is not positive.
std::vector<Label> body_labels(const BodySpec& spec, int dimension);

// Where a body's particles start (MODEL.md section 2): the labels' centroid at `centre`, linked
// labels `spacing` apart, i.e. centre + spacing (l - centroid).
std::vector<Vec3> placed_positions(const std::vector<Label>& labels, const Vec3& centre, double spacing);

// Each particle's mass M_l = K_l / 2: half the number of its links that reach another label of
// the set (MODEL.md section 2).
std::vector<double> link_masses(const std::vector<Label>& labels, const SolidTopology& topology);

// "<prefix>.<field>: <reason>" for every problem with the spec alone (not its placement).
std::vector<std::string> validate_body_spec(const BodySpec& spec, int dimension, const std::string& prefix);

}  // namespace lbsolid::solid
