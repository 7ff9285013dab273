#pragma once
// Where the fields the core names in its validation messages live in the API's Scenario. The core
// (scene/scene.cpp, fluid/fluid_config.cpp, solid/body_shape.cpp) says "<field>: <reason>" in its
// own terms; a client needs the path in the message it sent:
//   lattice, precision, exchange        -> scenario.<same>
//   nx, ny, nz                          -> scenario.domain.<same>
//   nx*ny*nz (grid too large)           -> scenario.domain
//   omega, rho0, body_force, threads,
//   streaming, collision, trt_magic     -> scenario.fluid.<same>
//   sides.<side> (the side's kind)      -> scenario.domain.<side>.kind
//   sides.<side>.<field>                -> scenario.domain.<side>.<same> (wall_velocity, traction,
//                                          inflow_speed, inflow_profile, outflow_density)
//   bodies                              -> scenario.bodies
//   bodies[b].<field>                   -> scenario.bodies[<index in the scenario>].<field>
//   contact.restitution                 -> scenario.contact.restitution
// Internal to scenario_translation.cpp; header-only because the API library is a single
// translation unit.
#include <charconv>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace lbsolid::server {

// The proto path of `field`, or nullopt for a field this table does not know. `original[b]` is
// the scenario's index of the core's body b (the core may be shown only some of the bodies).
inline std::optional<std::string> core_field_path(const std::string& field, const std::vector<int>& original) {
  static const std::map<std::string_view, std::string_view> kFixed = {
      {"lattice", "scenario.lattice"},
      {"precision", "scenario.precision"},
      {"exchange", "scenario.exchange"},
      {"nx", "scenario.domain.nx"},
      {"ny", "scenario.domain.ny"},
      {"nz", "scenario.domain.nz"},
      {"nx*ny*nz", "scenario.domain"},
      {"omega", "scenario.fluid.omega"},
      {"rho0", "scenario.fluid.rho0"},
      {"body_force", "scenario.fluid.body_force"},
      {"threads", "scenario.fluid.threads"},
      {"streaming", "scenario.fluid.streaming"},
      {"collision", "scenario.fluid.collision"},
      {"trt_magic", "scenario.fluid.trt_magic"},
      {"bodies", "scenario.bodies"},
      {"contact.restitution", "scenario.contact.restitution"},
      {"monitor.interval", "scenario.stability.check_interval"},
      {"monitor.max_mach", "scenario.stability.max_mach"},
      {"monitor.min_density", "scenario.stability.min_density"},
      {"monitor.max_density", "scenario.stability.max_density"},
  };
  if (const auto fixed = kFixed.find(field); fixed != kFixed.end()) return std::string(fixed->second);
  if (field.starts_with("sides.")) {
    // "sides.y_low" alone is about the side's kind (unknown, not allowed on that side, periodic on
    // one side of an axis only); "sides.y_low.traction" names its own field.
    const std::string side = field.substr(6);
    return "scenario.domain." + side + (side.find('.') == std::string::npos ? ".kind" : "");
  }
  if (field.starts_with("bodies[")) {
    const std::size_t close = field.find(']');
    if (close == std::string::npos) return std::nullopt;
    std::size_t b = 0;
    const auto [end, status] = std::from_chars(field.data() + 7, field.data() + close, b);
    if (status != std::errc() || end != field.data() + close || b >= original.size()) return std::nullopt;
    return "scenario.bodies[" + std::to_string(original[b]) + "]" + field.substr(close + 1);
  }
  return std::nullopt;
}

}  // namespace lbsolid::server
