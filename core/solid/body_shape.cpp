#include "solid/body_shape.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace lbsolid::solid {

const char* body_shape_name(BodyShape shape) {
  switch (shape) {
    case BodyShape::kRectangle: return "rectangle";
    case BodyShape::kDisk: return "disk";
    case BodyShape::kChain: return "chain";
    case BodyShape::kLabels: return "labels";
  }
  return "?";
}

std::vector<Vec3> placed_positions(const std::vector<Label>& labels, const Vec3& centre, double spacing) {
  Vec3 centroid{0, 0, 0};
  for (const auto& l : labels)
    for (int a = 0; a < 3; ++a) centroid[a] += l[a] / static_cast<double>(labels.size());
  std::vector<Vec3> positions;
  positions.reserve(labels.size());
  for (const auto& l : labels) {
    Vec3 r;
    for (int a = 0; a < 3; ++a) r[a] = centre[a] + spacing * (l[a] - centroid[a]);
    positions.push_back(r);
  }
  return positions;
}

std::vector<double> link_masses(const std::vector<Label>& labels, const SolidTopology& topology) {
  const std::set<Label> present(labels.begin(), labels.end());
  std::vector<double> masses;
  masses.reserve(labels.size());
  for (const auto& l : labels) {
    int links = 0;
    for (int k = 0; k < topology.links(); ++k) {
      const Label c = topology.link(k);
      links += present.count({l[0] + c[0], l[1] + c[1], l[2] + c[2]}) > 0;
    }
    masses.push_back(0.5 * links);
  }
  return masses;
}

std::vector<Label> body_labels(const BodySpec& spec, int dimension) {
  std::vector<Label> labels;
  switch (spec.shape) {
    case BodyShape::kRectangle: {
      const int nz = dimension == 3 ? spec.size[2] : 1;
      for (int k = 0; k < nz; ++k)
        for (int j = 0; j < spec.size[1]; ++j)
          for (int i = 0; i < spec.size[0]; ++i) labels.push_back({i, j, k});
      break;
    }
    case BodyShape::kDisk: {
      const int r = static_cast<int>(std::floor(spec.radius));
      const int rz = dimension == 3 ? r : 0;
      for (int k = -rz; k <= rz; ++k)
        for (int j = -r; j <= r; ++j)
          for (int i = -r; i <= r; ++i)
            if (i * i + j * j + k * k <= spec.radius * spec.radius) labels.push_back({i, j, k});
      break;
    }
    case BodyShape::kChain:
      for (int n = 0; n < spec.length; ++n) {
        Label l{0, 0, 0};
        l[spec.axis] = n;
        labels.push_back(l);
      }
      break;
    case BodyShape::kLabels:
      labels = spec.labels;
      break;
  }
  return labels;
}

std::vector<std::string> validate_body_spec(const BodySpec& spec, int dimension, const std::string& prefix) {
  std::vector<std::string> errors;
  auto error = [&](const std::string& field, const std::string& reason) {
    errors.push_back(prefix + "." + field + ": " + reason);
  };
  auto finite = [](const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); };
  switch (spec.shape) {
    case BodyShape::kRectangle:
      for (int a = 0; a < dimension; ++a)
        if (spec.size[a] < 1) error("size", "every extent must be at least 1 particle");
      if (dimension == 2 && spec.size[2] != 1) error("size", "a 2D rectangle has size[2] = 1");
      if (spec.size[0] * spec.size[1] * (dimension == 3 ? spec.size[2] : 1) < 2)
        error("size", "a body needs at least 2 particles (a lone particle has no link, so M = K/2 = 0)");
      break;
    case BodyShape::kDisk:
      if (!(spec.radius >= 1)) error("radius", "must be at least 1 (a smaller disk is one particle with no link)");
      break;
    case BodyShape::kChain:
      if (spec.length < 2) error("length", "a chain needs at least 2 particles");
      if (spec.axis < 0 || spec.axis >= dimension)
        error("axis", "must be 0 (x), 1 (y)" + std::string(dimension == 3 ? " or 2 (z)" : ""));
      break;
    case BodyShape::kLabels: {
      if (spec.labels.size() < 2) error("labels", "a body needs at least 2 particles");
      std::set<Label> seen;
      for (const Label& l : spec.labels) {
        if (dimension == 2 && l[2] != 0) {
          error("labels", "a 2D label has a zero third component");
          break;
        }
        if (!seen.insert(l).second) {
          error("labels", "label (" + std::to_string(l[0]) + ", " + std::to_string(l[1]) + ", " +
                              std::to_string(l[2]) + ") appears twice");
          break;
        }
      }
      if (errors.empty()) {
        const SolidTopology topology{dimension};
        for (const Label& l : spec.labels) {
          bool linked = false;
          for (int k = 0; k < topology.links(); ++k) {
            const Label c = topology.link(k);
            linked = linked || seen.count({l[0] + c[0], l[1] + c[1], l[2] + c[2]});
          }
          if (!linked) {
            error("labels", "label (" + std::to_string(l[0]) + ", " + std::to_string(l[1]) + ", " +
                                std::to_string(l[2]) + ") has no neighbour, so its mass M = K/2 would be 0");
            break;
          }
        }
      }
      break;
    }
  }
  if (!(spec.spacing > 0) || !std::isfinite(spec.spacing)) error("spacing", "must be a positive number");
  if (!finite(spec.centre)) error("centre", "must be finite");
  if (!finite(spec.velocity)) error("velocity", "must be finite");
  if (!finite(spec.load)) error("load", "must be finite");
  if (dimension == 2 && (spec.centre[2] != 0 || spec.velocity[2] != 0 || spec.load[2] != 0))
    error("centre/velocity/load", "a 2D body has zero z components");
  if (!finite(spec.angular_velocity)) error("angular_velocity", "must be finite");
  if (dimension == 2 && (spec.angular_velocity[0] != 0 || spec.angular_velocity[1] != 0))
    error("angular_velocity", "a 2D body spins about z only (x and y components zero)");
  if (spec.anchored && !spec.anchor_labels.empty())
    error("anchor_labels", "give either anchored (the whole body) or anchor_labels, not both");
  if ((spec.anchored || !spec.anchor_labels.empty()) && spec.rotation)
    error("rotation", "an anchored body cannot rotate (its springs' frame would turn about a fixed point)");
  const auto nonnegative = [](double x) { return std::isfinite(x) && x >= 0; };
  if (!nonnegative(spec.fracture.max_force)) error("fracture.max_force", "must be a finite number >= 0 (0: off)");
  if (!nonnegative(spec.fracture.max_stretch)) error("fracture.max_stretch", "must be a finite number >= 0 (0: off)");
  if (spec.fracture.enabled() && spec.rotation)
    error("rotation", "a body that can break cannot rotate (its best-fit frame would span the broken pieces)");
  for (const PointLoad& point : spec.point_loads) {
    if (!finite(point.force)) error("point_loads.force", "must be finite");
    else if (dimension == 2 && point.force[2] != 0) error("point_loads.force", "a 2D body has zero z components");
  }
  if ((!spec.anchor_labels.empty() || !spec.point_loads.empty()) && errors.empty()) {
    const std::vector<Label> labels = body_labels(spec, dimension);
    const std::set<Label> own(labels.begin(), labels.end());
    // Each label of `field` must be one of the body's, and appear once.
    const auto check_labels = [&](const char* field, const auto& items, const auto& label_of) {
      std::set<Label> seen;
      for (const auto& item : items) {
        const Label& l = label_of(item);
        const std::string text = "(" + std::to_string(l[0]) + ", " + std::to_string(l[1]) + ", " + std::to_string(l[2]) + ")";
        if (!own.count(l)) {
          error(field, "label " + text + " is not a particle of this body");
          break;
        }
        if (!seen.insert(l).second) {
          error(field, "label " + text + " appears twice");
          break;
        }
      }
    };
    check_labels("anchor_labels", spec.anchor_labels, [](const Label& l) -> const Label& { return l; });
    check_labels("point_loads.label", spec.point_loads, [](const PointLoad& p) -> const Label& { return p.label; });
  }
  return errors;
}

bool is_anchored(const BodySpec& spec, const Label& label) {
  if (spec.anchored) return true;
  for (const Label& l : spec.anchor_labels)
    if (l == label) return true;
  return false;
}

}  // namespace lbsolid::solid
