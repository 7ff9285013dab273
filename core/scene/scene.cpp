#include "scene/scene.h"

#include <cmath>
#include <cstdio>

namespace lbsolid::scene {

const char* lattice_kind_name(LatticeKind lattice) {
  switch (lattice) {
    case LatticeKind::kD2Q9: return "D2Q9";
    case LatticeKind::kD2Q7: return "D2Q7";
    case LatticeKind::kD3Q19: return "D3Q19";
  }
  return "?";
}

int lattice_dimension(LatticeKind lattice) { return lattice == LatticeKind::kD3Q19 ? 3 : 2; }

namespace {

bool valid_lattice(LatticeKind l) {
  return l == LatticeKind::kD2Q9 || l == LatticeKind::kD2Q7 || l == LatticeKind::kD3Q19;
}

double axis_spacing(const Scene& scene, int axis) {
  return scene.lattice == LatticeKind::kD2Q7 && axis == 1 ? std::sqrt(3.0) / 2.0 : 1.0;
}

std::string format_position(const solid::Vec3& r, int dimension) {
  char buffer[96];
  if (dimension == 3)
    std::snprintf(buffer, sizeof buffer, "(%.3g, %.3g, %.3g)", r[0], r[1], r[2]);
  else
    std::snprintf(buffer, sizeof buffer, "(%.3g, %.3g)", r[0], r[1]);
  return buffer;
}

// Every particle of the body must start inside the box, on the fluid's side of every wall.
void check_placement(const Scene& scene, const solid::BodySpec& spec, const std::string& prefix,
                     std::vector<std::string>& errors) {
  const int dimension = lattice_dimension(scene.lattice);
  const auto labels = solid::body_labels(spec, dimension);
  solid::Vec3 centroid{0, 0, 0};
  for (const auto& l : labels)
    for (int a = 0; a < 3; ++a) centroid[a] += l[a] / static_cast<double>(labels.size());
  for (const auto& l : labels) {
    solid::Vec3 r;
    for (int a = 0; a < 3; ++a) r[a] = spec.centre[a] + spec.spacing * (l[a] - centroid[a]);
    for (int side = 0; side < 2 * dimension; ++side) {
      if (scene.fluid.sides[side].kind == fluid::WallKind::kPeriodic) continue;
      const int axis = side / 2;
      const double wall = wall_position(scene, side);
      if ((side % 2 == 0 && !(r[axis] > wall)) || (side % 2 == 1 && !(r[axis] < wall))) {
        errors.push_back(prefix + ".centre: particle at " + format_position(r, dimension) +
                         " lies on or beyond the " + fluid::side_name(side) + " wall (at " +
                         std::to_string(wall) + ")");
        return;
      }
    }
  }
}

}  // namespace

double wall_position(const Scene& scene, int side) {
  const int axis = side / 2;
  const int n[3] = {scene.fluid.nx, scene.fluid.ny, scene.fluid.nz};
  const double spacing = axis_spacing(scene, axis);
  return side % 2 == 0 ? -0.5 * spacing : (n[axis] - 0.5) * spacing;
}

std::string body_name(const Scene& scene, std::size_t b) {
  return scene.bodies[b].name.empty() ? "body" + std::to_string(b) : scene.bodies[b].name;
}

std::vector<std::string> validate_scene(const Scene& scene) {
  std::vector<std::string> errors;
  if (!valid_lattice(scene.lattice)) {
    errors.push_back("lattice: unknown lattice " + std::to_string(static_cast<int>(scene.lattice)) +
                     "; use D2Q9, D2Q7 or D3Q19");
    return errors;
  }
  if (scene.precision != Precision::kDouble && scene.precision != Precision::kFloat)
    errors.push_back("precision: unknown precision; use double or float");
  const int dimension = lattice_dimension(scene.lattice);
  // The fluid's rules also check the box (grid size, sides) of a scene without fluid.
  for (const auto& e : fluid::validate_fluid_config(scene.fluid, dimension, scene.lattice == LatticeKind::kD2Q7))
    errors.push_back(e);
  if (!scene.with_fluid) {
    const auto& f = scene.fluid.body_force;
    if (f[0] != 0 || f[1] != 0 || f[2] != 0)
      errors.push_back("body_force: is set but the scene has no fluid to push");
    if (scene.bodies.empty()) errors.push_back("bodies: a scene without fluid needs at least one body");
  }
  if (!(scene.contact.restitution >= 0.0 && scene.contact.restitution <= 1.0))
    errors.push_back("contact.restitution: must lie in [0, 1], got " + std::to_string(scene.contact.restitution));
  if (scene.exchange != coupling::ExchangeRule::kCommonVelocity && scene.exchange != coupling::ExchangeRule::kPairwise)
    errors.push_back("exchange: unknown rule; use common-velocity or pairwise");
  // Placement needs only a box with a size; other errors do not hide a misplaced body.
  const bool box_ok = scene.fluid.nx >= 1 && scene.fluid.ny >= 1 && scene.fluid.nz >= 1;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const std::string prefix = "bodies[" + std::to_string(b) + "]";
    const auto body_errors = solid::validate_body_spec(scene.bodies[b], dimension, prefix);
    errors.insert(errors.end(), body_errors.begin(), body_errors.end());
    if (body_errors.empty() && box_ok) check_placement(scene, scene.bodies[b], prefix, errors);
  }
  // Output (H5MD groups, particle streams) names bodies: each name must be unique.
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    for (std::size_t a = 0; a < b; ++a)
      if (body_name(scene, a) == body_name(scene, b)) {
        errors.push_back("bodies[" + std::to_string(b) + "].name: \"" + body_name(scene, b) +
                         "\" is already the name of bodies[" + std::to_string(a) + "]");
        break;
      }
  return errors;
}

}  // namespace lbsolid::scene
