#include "scene/scene.h"

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <map>
#include <set>
#include <unordered_map>
#include <utility>

#include "coupling/node_locator.h"
#include "lattice/d2q7.h"
#include "lattice/d2q9.h"
#include "lattice/d3q19.h"

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

double axis_spacing(const Scene& scene, int axis) { return axis == 1 ? lattice_row_spacing(scene.lattice) : 1.0; }

// fn(descriptor) for the scene's lattice.
template <class Fn>
double with_descriptor(LatticeKind kind, Fn fn) {
  switch (kind) {
    case LatticeKind::kD2Q7: return fn(lattice::D2Q7{});
    case LatticeKind::kD3Q19: return fn(lattice::D3Q19{});
    case LatticeKind::kD2Q9: break;
  }
  return fn(lattice::D2Q9{});
}

std::string format_position(const solid::Vec3& r, int dimension) {
  char buffer[96];
  if (dimension == 3)
    std::snprintf(buffer, sizeof buffer, "(%.3g, %.3g, %.3g)", r[0], r[1], r[2]);
  else
    std::snprintf(buffer, sizeof buffer, "(%.3g, %.3g)", r[0], r[1]);
  return buffer;
}

// Shortest form of a number for messages ("1.97", not std::to_string's "1.970000").
std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", v);
  return buffer;
}

// Every particle of the body must start at a finite position inside the box, on the fluid's side
// of every wall. A finite spacing times a long extent can still overflow to infinity.
void check_placement(const Scene& scene, const solid::BodySpec& spec, const std::string& prefix,
                     std::vector<std::string>& errors) {
  const int dimension = lattice_dimension(scene.lattice);
  for (const auto& r : solid::placed_positions(solid::body_labels(spec, dimension), spec.centre, spec.spacing)) {
    if (!std::isfinite(r[0]) || !std::isfinite(r[1]) || !std::isfinite(r[2])) {
      errors.push_back(prefix + ".spacing: " + number(spec.spacing) +
                       " times the body's extent puts particles at non-finite positions");
      return;
    }
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

double sound_speed(LatticeKind lattice) { return std::sqrt(lattice_cs2(lattice)); }

double mach(const Scene& scene, const solid::Vec3& u) {
  return std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) / sound_speed(scene.lattice);
}

// The Mach number of the fastest particle of a spinning body at the start: its velocity plus the
// spin's at the particle farthest from the centre of mass (solid::SolidSystem::add_body).
double initial_rim_mach(const Scene& scene, const solid::BodySpec& spec) {
  const int dimension = lattice_dimension(scene.lattice);
  const auto labels = solid::body_labels(spec, dimension);
  const auto masses = solid::link_masses(labels, solid::SolidTopology{dimension});
  solid::Vec3 centre{0, 0, 0};
  double mass = 0;
  for (std::size_t p = 0; p < labels.size(); ++p) {
    mass += masses[p];
    for (int a = 0; a < 3; ++a) centre[a] += masses[p] * spec.spacing * labels[p][a];
  }
  double fastest = mach(scene, spec.velocity);
  if (!(mass > 0)) return fastest;
  const auto& w = spec.angular_velocity;
  for (const auto& l : labels) {
    solid::Vec3 r;
    for (int a = 0; a < 3; ++a) r[a] = spec.spacing * l[a] - centre[a] / mass;
    const solid::Vec3 u{spec.velocity[0] + w[1] * r[2] - w[2] * r[1], spec.velocity[1] + w[2] * r[0] - w[0] * r[2],
                        spec.velocity[2] + w[0] * r[1] - w[1] * r[0]};
    fastest = std::max(fastest, mach(scene, u));
  }
  return fastest;
}

void check_monitor(const MonitorSpec& m, std::vector<std::string>& errors) {
  if (m.interval < 0)
    errors.push_back("monitor.interval: must be 0 (off) or a number of steps, got " + std::to_string(m.interval));
  // NaN fails every comparison, so each test is written to be false for it.
  const auto& l = m.limits;
  if (!(l.max_mach > 0)) errors.push_back("monitor.max_mach: must be positive, got " + number(l.max_mach));
  if (!(l.min_density >= 0 && l.min_density < 1))
    errors.push_back("monitor.min_density: must lie in [0, 1) (a fraction of rho0), got " + number(l.min_density));
  if (!(l.max_density > 1))
    errors.push_back("monitor.max_density: must be above 1 (a multiple of rho0; infinity for none), got " +
                     number(l.max_density));
}

// An inlet's speed and an outlet's density against what the fluid can carry and, with the
// monitor on, against its limits: a side that breaks them would stop the run at its first check.
void check_open_side(const Scene& scene, int side, std::vector<std::string>& errors) {
  const auto& b = scene.fluid.sides[side];
  const std::string field = std::string("sides.") + fluid::side_name(side);
  const auto& limits = scene.monitor.limits;
  const bool monitored = scene.monitor.interval > 0;
  if (b.kind == fluid::WallKind::kVelocityInlet) {
    const double m = std::abs(b.inflow_speed) / sound_speed(scene.lattice);
    if (!(m < 1))
      errors.push_back(field + ".inflow_speed: Mach number " + number(m) + " must stay below 1");
    else if (monitored && !(m < limits.max_mach))
      errors.push_back(field + ".inflow_speed: Mach number " + number(m) + " reaches the monitor's max_mach " +
                       number(limits.max_mach));
  }
  if (b.kind == fluid::WallKind::kPressureOutlet && b.outflow_density > 0) {
    const double ratio = b.outflow_density / scene.fluid.rho0;
    if (monitored && !(ratio > limits.min_density && ratio < limits.max_density))
      errors.push_back(field + ".outflow_density: " + number(b.outflow_density) + " lies outside the monitor's band (" +
                       number(limits.min_density * scene.fluid.rho0) + ", " +
                       number(limits.max_density * scene.fluid.rho0) + ")");
  }
}

// Speeds at or above the speed of sound cannot be stable: the equilibrium is a low-Mach
// expansion whose populations go negative near Mach 1, and a particle coupled to a node moving
// that fast drags it there in one step.
void check_speeds(const Scene& scene, std::vector<std::string>& errors) {
  if (!scene.with_fluid) return;
  for (int side = 0; side < 2 * lattice_dimension(scene.lattice); ++side) {
    const auto& b = scene.fluid.sides[side];
    if (b.kind == fluid::WallKind::kMovingWall && !(mach(scene, b.wall_velocity) < 1))
      errors.push_back(std::string("sides.") + fluid::side_name(side) + ".wall_velocity: Mach number " +
                       number(mach(scene, b.wall_velocity)) + " must stay below 1");
    check_open_side(scene, side, errors);
  }
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    if (!(mach(scene, scene.bodies[b].velocity) < 1))
      errors.push_back("bodies[" + std::to_string(b) + "].velocity: initial Mach number " +
                       number(mach(scene, scene.bodies[b].velocity)) + " must stay below 1");
    else if (scene.bodies[b].angular_velocity != solid::Vec3{0, 0, 0})
      if (const double rim = initial_rim_mach(scene, scene.bodies[b]); !(rim < 1))
        errors.push_back("bodies[" + std::to_string(b) + "].angular_velocity: the fastest particle's initial Mach number " +
                         number(rim) + " must stay below 1");
  }
}

// The cell of the node nearest to each position, at the start, on the scene's lattice.
template <class L>
std::vector<long> nearest_cells(const Scene& scene, const std::vector<solid::Vec3>& positions) {
  const coupling::NodeLocator<L> locator(scene.fluid);
  std::vector<long> cells;
  cells.reserve(positions.size());
  for (const auto& r : positions) cells.push_back(locator.cell(locator.nearest(r)));
  return cells;
}

std::vector<long> nearest_cells(const Scene& scene, const std::vector<solid::Vec3>& positions) {
  switch (scene.lattice) {
    case LatticeKind::kD2Q9: return nearest_cells<lattice::D2Q9>(scene, positions);
    case LatticeKind::kD2Q7: return nearest_cells<lattice::D2Q7>(scene, positions);
    case LatticeKind::kD3Q19: return nearest_cells<lattice::D3Q19>(scene, positions);
  }
  return {};
}

// The pairwise rule (eq. 14 per particle) moves a node holding particles p by sum_p Z_p / rho0 of
// each velocity difference and particle p by Z_p / M_p, Z_p = 1 / (1/rho0 + 1/M_p). Once the two
// together reach 2 the exchange at that node over-corrects by more than the difference it corrects:
// with bulk particles (M = 2) and rho0 = 1 that is 3 particles at one node. Streaming spreads the
// excess, so a few such nodes may stay bounded (the dense suspension hard case: bounded at 2
// particles per node on average, whose densest nodes hold 4; diverging from 3 on average), hence a
// warning, not a refusal. Returns the worst node's sum and its particle count.
std::pair<double, int> pairwise_overcorrection(const Scene& scene) {
  const int dimension = lattice_dimension(scene.lattice);
  std::map<long, std::pair<double, double>> at;  // cell -> (sum Z/rho0, largest Z/M)
  std::map<long, int> count;
  for (const auto& spec : scene.bodies) {
    const auto labels = solid::body_labels(spec, dimension);
    const auto masses = solid::link_masses(labels, solid::SolidTopology{dimension});
    const auto cells = nearest_cells(scene, solid::placed_positions(labels, spec.centre, spec.spacing));
    for (std::size_t p = 0; p < labels.size(); ++p) {
      const double z = 1.0 / (1.0 / scene.fluid.rho0 + 1.0 / masses[p]);
      auto& node = at[cells[p]];
      node.first += z / scene.fluid.rho0;
      node.second = std::max(node.second, z / masses[p]);
      ++count[cells[p]];
    }
  }
  std::pair<double, int> worst{0, 0};
  for (const auto& [cell, node] : at)
    if (node.first + node.second > worst.first) worst = {node.first + node.second, count[cell]};
  return worst;
}

// A name as messages echo it: at most 64 bytes (cut on a UTF-8 character boundary), so that a
// list of problems stays short enough for a client to receive.
std::string echoed_name(const std::string& name) {
  constexpr std::size_t kMaxEcho = 64;
  if (name.size() <= kMaxEcho) return name;
  std::size_t end = kMaxEcho;  // back over at most 3 continuation bytes (10xxxxxx)
  for (int back = 0; back < 3 && (static_cast<unsigned char>(name[end]) & 0xC0) == 0x80; ++back) --end;
  return name.substr(0, end) + "...";
}

// Output (H5MD groups, particle streams) names bodies: each name must be unique. One error per
// shared name, on its second body, with how many share it; a hash map keeps 10^5 bodies cheap.
void check_unique_names(const Scene& scene, std::vector<std::string>& errors) {
  struct Uses {
    std::size_t first, second = 0, last = 0, count = 1;
  };
  std::unordered_map<std::string, Uses> uses(2 * scene.bodies.size());
  std::vector<const std::pair<const std::string, Uses>*> shared;  // in the order of their second body
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const auto [it, inserted] = uses.try_emplace(body_name(scene, b), Uses{b});
    if (inserted) continue;
    Uses& u = it->second;
    if (++u.count == 2) {
      u.second = b;
      shared.push_back(&*it);  // elements of an unordered_map stay where they are on rehash
    }
    u.last = b;
  }
  for (const auto* entry : shared) {
    const Uses& u = entry->second;
    std::string error = "bodies[" + std::to_string(u.second) + "].name: \"" + echoed_name(entry->first) +
                        "\" is already the name of bodies[" + std::to_string(u.first) + "]";
    if (u.count > 2)
      error += " (" + std::to_string(u.count) + " bodies share this name; the last is bodies[" +
               std::to_string(u.last) + "])";
    errors.push_back(std::move(error));
  }
}

}  // namespace

double lattice_cs2(LatticeKind lattice) {
  return with_descriptor(lattice, [](auto descriptor) { return decltype(descriptor)::cs2; });
}

double lattice_row_spacing(LatticeKind lattice) {
  return with_descriptor(lattice, [](auto descriptor) {
    using L = decltype(descriptor);
    if constexpr (L::hexagonal) return L::row_spacing;
    return 1.0;
  });
}

double wall_position(const Scene& scene, int side) {
  const int axis = side / 2;
  const int n[3] = {scene.fluid.nx, scene.fluid.ny, scene.fluid.nz};
  // D2Q7 x sides: rows alternate between nodes at 0 .. nx - 1 and 1/2 .. nx - 1/2, so the wall is a
  // zig-zag; the links it cuts at a slant (the only ones carrying momentum along it) are cut
  // half-way at -1/4 and nx - 1/4, the mean of all its cut points too. A Poiseuille flow along y
  // sees the walls there (tests/fluid/d2q7_x_walls_test.cpp).
  if (scene.lattice == LatticeKind::kD2Q7 && axis == 0) return side % 2 == 0 ? -0.25 : n[0] - 0.25;
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
  // Anchors: held by the common velocity (u* = 0 at their nodes); not beside rotating bodies,
  // whose stage records torques instead (stages/solid_stage.h).
  bool any_rotating = false;
  for (const auto& body : scene.bodies) any_rotating = any_rotating || body.rotation;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const auto& body = scene.bodies[b];
    if (!body.anchored && body.anchor_labels.empty()) continue;
    const std::string field = "bodies[" + std::to_string(b) + "]." + (body.anchored ? "anchored" : "anchor_labels");
    if (scene.exchange == coupling::ExchangeRule::kPairwise)
      errors.push_back(field + ": anchors need the common-velocity exchange rule");
    if (any_rotating && !body.rotation)
      errors.push_back(field + ": a scene with rotating bodies cannot have anchors yet");
  }
  // Fracture: a shed particle (M = 0) takes no part in the exchange, which the pairwise rule's
  // 1/M cannot express; beside rotating bodies the torque record would keep a shed particle's last
  // force.
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    if (!scene.bodies[b].fracture.enabled()) continue;
    const std::string field = "bodies[" + std::to_string(b) + "].fracture";
    if (scene.exchange == coupling::ExchangeRule::kPairwise && scene.with_fluid)
      errors.push_back(field + ": breaking bodies need the common-velocity exchange rule");
    if (any_rotating && !scene.bodies[b].rotation)
      errors.push_back(field + ": a scene with rotating bodies cannot have breaking bodies yet");
  }
  // Placement needs only a box with a size; other errors do not hide a misplaced body.
  const bool box_ok = scene.fluid.nx >= 1 && scene.fluid.ny >= 1 && scene.fluid.nz >= 1;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const std::string prefix = "bodies[" + std::to_string(b) + "]";
    const auto body_errors = solid::validate_body_spec(scene.bodies[b], dimension, prefix);
    errors.insert(errors.end(), body_errors.begin(), body_errors.end());
    if (body_errors.empty() && box_ok) check_placement(scene, scene.bodies[b], prefix, errors);
  }
  check_monitor(scene.monitor, errors);
  check_speeds(scene, errors);
  check_unique_names(scene, errors);
  return errors;
}

std::vector<std::string> scene_warnings(const Scene& scene) {
  std::vector<std::string> warnings;
  // BGK's viscosity (1/omega - 1/2) c_s^2 vanishes at omega = 2; above 1.95 (nu < 0.0085 on D2Q9)
  // the smallest under-resolved gradient can set off the instability the hard cases show.
  if (scene.with_fluid && scene.fluid.omega > 1.95)
    warnings.push_back("omega: " + number(scene.fluid.omega) +
                       " is above 1.95; the fluid is close to its stability limit");
  // Compressibility errors grow as Mach^2: above 0.1 they pass 1% and the density band and Mach
  // limit of the monitor come within reach of the first transients.
  constexpr double kMachWarning = 0.1;
  if (!scene.with_fluid) return warnings;
  for (int side = 0; side < 2 * lattice_dimension(scene.lattice); ++side) {
    const auto& b = scene.fluid.sides[side];
    const double m = mach(scene, b.wall_velocity);
    if (b.kind == fluid::WallKind::kMovingWall && m > kMachWarning)
      warnings.push_back(std::string("sides.") + fluid::side_name(side) + ".wall_velocity: Mach number " + number(m) +
                         " is above " + number(kMachWarning));
    const double inflow = std::abs(b.inflow_speed) / sound_speed(scene.lattice);
    if (b.kind == fluid::WallKind::kVelocityInlet && inflow > kMachWarning)
      warnings.push_back(std::string("sides.") + fluid::side_name(side) + ".inflow_speed: Mach number " +
                         number(inflow) + " is above " + number(kMachWarning));
  }
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const double m = mach(scene, scene.bodies[b].velocity);
    if (m > kMachWarning)
      warnings.push_back("bodies[" + std::to_string(b) + "].velocity: initial Mach number " + number(m) +
                         " is above " + number(kMachWarning));
    else if (scene.bodies[b].angular_velocity != solid::Vec3{0, 0, 0})
      if (const double rim = initial_rim_mach(scene, scene.bodies[b]); rim > kMachWarning)
        warnings.push_back("bodies[" + std::to_string(b) + "].angular_velocity: the fastest particle's initial Mach number " +
                           number(rim) + " is above " + number(kMachWarning));
  }
  if (scene.exchange == coupling::ExchangeRule::kPairwise && !scene.bodies.empty()) {
    const auto [factor, particles] = pairwise_overcorrection(scene);
    if (factor >= 2)
      warnings.push_back("exchange: pairwise with " + std::to_string(particles) +
                         " particles at one node over-corrects (sum Z/rho0 + Z/M = " + number(factor) +
                         " >= 2) and can diverge; use common-velocity");
  }
  return warnings;
}

double body_mass_ratio(const Scene& scene, std::size_t b) {
  const solid::BodySpec& spec = scene.bodies.at(b);
  const int dimension = lattice_dimension(scene.lattice);
  const auto labels = solid::body_labels(spec, dimension);
  if (labels.empty()) return 0;
  double mass = 0;
  for (double m : solid::link_masses(labels, solid::SolidTopology{dimension})) mass += m;
  const auto cells = nearest_cells(scene, solid::placed_positions(labels, spec.centre, spec.spacing));
  const auto nodes = std::set<long>(cells.begin(), cells.end()).size();
  return mass / static_cast<double>(nodes) / scene.fluid.rho0;
}

}  // namespace lbsolid::scene
