// Scenario (proto) -> core::Scene in three passes:
//   1. translate, filling the proto's documented defaults and checking what only the message can
//      say: required fields, unknown enum numbers, fields of another shape, the API's size limits;
//   2. run the core's validate_scene on the translation (the one source of the physics rules);
//   3. rewrite each core "<field>: reason" as "scenario.<path>: reason", dropping those that
//      restate a problem pass 1 already reported on the same field.
// Every problem is kept: a client fixes a scenario in one round trip, not one per error
// (error_summary.h says how many of them it is sent). Every pass is linear or n log n in the
// number of bodies and problems (hash sets, never a pass over the others per item): 10^5 bodies
// once took minutes. tests/bench/translation_bench.cpp measures it.
#include "io/api/scenario_translation.h"

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>
#include <google/protobuf/unknown_field_set.h>
#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string_view>
#include <unordered_set>

#include "io/api/core_field_paths.h"
#include "io/api/enum_mapping.h"
#include "io/api/json_locator.h"

namespace lbsolid::server {
namespace {

namespace v1 = lbsolid::v1;
namespace pb = google::protobuf;

// The API's own limits, looser than any machine's memory but tight enough that validating a
// scenario stays cheap and free of integer overflow in the core's arithmetic.
constexpr double kMaxNodes = 2147483648.0;        // 2^31 fluid nodes
constexpr double kMaxBodyParticles = 16777216.0;  // 2^24 labels per body: validation lists them all
constexpr int kMaxLabelComponent = 1 << 30;       // the core adds +-1 to label components
// Each fluid thread is an OS thread started when the simulation is built; the core checks only >= 1.
constexpr int kMaxThreads = 256;
// Names are labels a person reads (logs, session lists, a terminal) and keys of output (H5MD groups,
// streams): 256 bytes is ample for either, and with 20 problems in a summary (error_summary.h),
// each echoing at most 64 bytes of a name, keeps what a client is sent small.
constexpr std::size_t kMaxNameBytes = 256;

struct Problem {
  std::string path;  // "scenario.fluid.omega"
  std::string reason;
  // Whether the problem also stands for everything under its path (a missing domain covers the
  // core's "nx: must be at least 1" and "ny: ...").
  bool covers_subfields = false;
};
using Problems = std::vector<Problem>;

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

// "unknown value 7; use LATTICE_D2Q9, LATTICE_D2Q7 or LATTICE_D3Q19"
std::string unknown_enum(const pb::EnumDescriptor* type, int value) {
  std::vector<std::string> names;
  for (int v = 0; v < type->value_count(); ++v)
    if (type->value(v)->number() != 0) names.push_back(type->value(v)->name());
  std::string list;
  for (std::size_t n = 0; n < names.size(); ++n)
    list += (n == 0 ? "" : n + 1 == names.size() ? " or " : ", ") + names[n];
  return "unknown value " + std::to_string(value) + "; use " + list;
}

// An unknown number (proto3 keeps those) is reported and passed on as the same number, which the
// core's own checks then reject too (on the same field, so that report is dropped).
template <class Core, class Proto>
Core enum_or_report(std::optional<Core> mapped, Proto value, const pb::EnumDescriptor* type, const std::string& path,
                    Problems& problems) {
  if (mapped) return *mapped;
  problems.push_back({path, unknown_enum(type, value)});
  return static_cast<Core>(value);
}

// ---- Names.

// The first character in `name` that breaks a line or controls a terminal: an ASCII control
// character or DEL, a C1 control (U+0080-U+009F, 0xC2 0x80-0x9F in UTF-8; protobuf has checked
// that a string field is UTF-8), or U+2028/U+2029. Described with its byte offset; empty if none.
std::string control_character(const std::string& name) {
  const auto byte = [&](std::size_t k) { return k < name.size() ? static_cast<unsigned char>(name[k]) : 0; };
  char text[64];
  for (std::size_t i = 0; i < name.size(); ++i) {
    unsigned code_point = 0;
    if (byte(i) < 0x20 || byte(i) == 0x7F)
      code_point = byte(i);
    else if (byte(i) == 0xC2 && byte(i + 1) >= 0x80 && byte(i + 1) <= 0x9F)
      code_point = byte(i + 1);
    else if (byte(i) == 0xE2 && byte(i + 1) == 0x80 && (byte(i + 2) == 0xA8 || byte(i + 2) == 0xA9))
      code_point = 0x2000 + byte(i + 2) - 0x80;
    else
      continue;
    std::snprintf(text, sizeof text, "U+%04X at byte %zu", code_point, i);
    return text;
  }
  return "";
}

// A name is one line of at most kMaxNameBytes.
void check_name(const std::string& name, const std::string& path, Problems& problems) {
  if (name.size() > kMaxNameBytes)
    problems.push_back({path, std::to_string(name.size()) + " bytes, more than the limit of " +
                                  std::to_string(kMaxNameBytes)});
  if (const std::string found = control_character(name); !found.empty())
    problems.push_back({path, "a name is one line of printable text; it holds the control character " + found});
}

// ---- Message fields. `dimension` is 2 or 3, or 0 when the lattice is unknown (then nothing that
// depends on it is checked, and the core is not asked).

// The proto documents z as ignored in 2D, so it is dropped here rather than reported.
fluid::Vec3 vec(const v1::Vector3& v, int dimension) { return {v.x(), v.y(), dimension == 2 ? 0.0 : v.z()}; }

bool nonzero(const v1::Vector3& v) { return v.x() != 0 || v.y() != 0 || v.z() != 0; }

void translate_domain(const v1::Scenario& in, int dimension, scene::Scene& out, Problems& problems) {
  const v1::Domain& d = in.domain();
  fluid::FluidConfig& f = out.fluid;
  f.nx = d.nx();
  f.ny = d.ny();
  f.nz = d.has_nz() ? d.nz() : 1;
  if (!in.has_domain()) {
    problems.push_back({"scenario.domain", "required: the box's nodes along x and y (nx, ny >= 1)", true});
  } else {
    const int n[3] = {f.nx, f.ny, f.nz};
    bool sized = true;
    for (int a = 0; a < 3; ++a) {
      if (n[a] >= 1) continue;
      problems.push_back(
          {std::string("scenario.domain.n") + "xyz"[a], "must be at least 1, got " + std::to_string(n[a])});
      sized = false;
    }
    if (dimension == 2 && f.nz > 1) {
      problems.push_back({"scenario.domain.nz", std::string("must be 1 on a 2D lattice (") +
                                                    scene::lattice_kind_name(out.lattice) + "), got " +
                                                    std::to_string(f.nz)});
      sized = false;
    }
    // In double: the product of three int32 can overflow 64 bits.
    const double nodes = static_cast<double>(f.nx) * f.ny * f.nz;
    if (sized && nodes > kMaxNodes) {
      problems.push_back({"scenario.domain", std::to_string(f.nx) + " x " + std::to_string(f.ny) + " x " +
                                                 std::to_string(f.nz) + " = " + number(nodes) +
                                                 " nodes, more than the limit of 2^31 (2147483648)"});
    }
  }
  const v1::Side* sides[6] = {&d.x_low(), &d.x_high(), &d.y_low(), &d.y_high(), &d.z_low(), &d.z_high()};
  for (int s = 0; s < 6; ++s) {
    const std::string path = std::string("scenario.domain.") + fluid::side_name(s);
    fluid::SideBoundary& side = f.sides[s];
    side.kind = enum_or_report(wall_kind_of(sides[s]->kind()), sides[s]->kind(), v1::WallKind_descriptor(),
                               path + ".kind", problems);
    side.wall_velocity = vec(sides[s]->wall_velocity(), dimension);
    side.traction = vec(sides[s]->traction(), dimension);
    side.inflow_speed = sides[s]->inflow_speed();
    side.inflow_profile = enum_or_report(inflow_profile_of(sides[s]->inflow_profile()), sides[s]->inflow_profile(),
                                         v1::InflowProfile_descriptor(), path + ".inflow_profile", problems);
    // The core takes 0 for rho0; a density set to 0 is an error, not the default.
    side.outflow_density = sides[s]->has_outflow_density() ? sides[s]->outflow_density() : 0.0;
    if (sides[s]->has_outflow_density() && sides[s]->outflow_density() == 0.0)
      problems.push_back({path + ".outflow_density", "must be a positive density (leave it unset for rho0)"});
    // The core skips the z sides of a 2D lattice (it rejects only their kind); a vector set there
    // would be silently lost.
    if (dimension == 2 && s >= fluid::kZLow) {
      if (nonzero(sides[s]->wall_velocity()))
        problems.push_back({path + ".wall_velocity", "a 2D lattice has no z sides"});
      if (nonzero(sides[s]->traction())) problems.push_back({path + ".traction", "a 2D lattice has no z sides"});
    }
  }
}

void translate_fluid(const v1::Fluid& in, int dimension, scene::Scene& out, Problems& problems) {
  out.with_fluid = !in.has_enabled() || in.enabled();
  fluid::FluidConfig& f = out.fluid;
  f.omega = in.has_omega() ? in.omega() : 1.0;
  f.rho0 = in.has_rho0() ? in.rho0() : 1.0;
  f.body_force = vec(in.body_force(), dimension);
  f.threads = in.has_threads() ? in.threads() : 1;
  if (f.threads > kMaxThreads)
    problems.push_back({"scenario.fluid.threads",
                        "must be at most " + std::to_string(kMaxThreads) + ", got " + std::to_string(f.threads)});
  f.streaming = enum_or_report(streaming_of(in.streaming()), in.streaming(), v1::Streaming_descriptor(),
                               "scenario.fluid.streaming", problems);
  f.collision = enum_or_report(collision_of(in.collision()), in.collision(), v1::Collision_descriptor(),
                               "scenario.fluid.collision", problems);
  f.trt_magic = in.has_trt_magic() ? in.trt_magic() : 3.0 / 16.0;
}

// ---- Bodies.

struct TranslatedBody {
  solid::BodySpec spec;
  // False when the core must not see the body: no shape to check, or one too large to list.
  bool core_can_check = true;
};

std::string axes_named(int dimension) { return dimension == 3 ? "x, y and z" : "x and y"; }

bool translate_rectangle(const v1::Body& in, const std::string& path, int dimension, solid::BodySpec& spec,
                         Problems& problems) {
  if (dimension == 0) return false;
  if (in.size_size() != dimension) {
    problems.push_back({path + ".size", "a rectangle needs " + std::to_string(dimension) + " values (particles along " +
                                            axes_named(dimension) + "), got " + std::to_string(in.size_size())});
    return false;
  }
  double particles = 1;
  bool positive = true;
  for (int a = 0; a < dimension; ++a) {
    spec.size[a] = in.size(a);
    positive = positive && spec.size[a] >= 1;
    particles *= spec.size[a];
  }
  spec.size[2] = dimension == 3 ? in.size(2) : 1;
  if (positive && particles > kMaxBodyParticles) {
    problems.push_back({path + ".size", number(particles) + " particles, more than the limit of 2^24 per body"});
    return false;
  }
  return true;  // extents below 1 are the core's to report
}

bool translate_disk(const v1::Body& in, const std::string& path, int dimension, solid::BodySpec& spec,
                    Problems& problems) {
  spec.radius = in.radius();
  if (!std::isfinite(spec.radius)) {
    problems.push_back({path + ".radius", "must be a finite number, got " + number(spec.radius)});
    return false;
  }
  if (dimension == 0) return false;
  // The core tries every label of the (2r + 1)^D cube around the centre.
  const double candidates = std::pow(2 * std::floor(std::max(spec.radius, 0.0)) + 1, dimension);
  if (candidates > kMaxBodyParticles) {
    problems.push_back({path + ".radius", "a disk of radius " + number(spec.radius) + " spans " + number(candidates) +
                                              " labels, more than the limit of 2^24 per body"});
    return false;
  }
  return true;
}

bool translate_chain(const v1::Body& in, const std::string& path, int dimension, solid::BodySpec& spec,
                     Problems& problems) {
  spec.length = in.length();
  const std::optional<int> axis = axis_of(in.axis());
  if (!axis) problems.push_back({path + ".axis", unknown_enum(v1::Axis_descriptor(), in.axis())});
  // -1 for an unknown axis: the core rejects it too, on the same field.
  spec.axis = axis.value_or(-1);
  if (dimension == 2 && spec.axis == 2)
    problems.push_back({path + ".axis", "AXIS_Z on a 2D lattice; use AXIS_X or AXIS_Y"});
  if (spec.length > kMaxBodyParticles) {
    problems.push_back(
        {path + ".length", std::to_string(spec.length) + " particles, more than the limit of 2^24 per body"});
    return false;
  }
  return true;
}

bool translate_labels(const v1::Body& in, const std::string& path, solid::BodySpec& spec, Problems& problems) {
  if (in.labels_size() > kMaxBodyParticles) {
    problems.push_back(
        {path + ".labels", std::to_string(in.labels_size()) + " particles, more than the limit of 2^24 per body"});
    return false;
  }
  bool in_range = true;
  for (int n = 0; n < in.labels_size(); ++n) {
    const v1::Label& l = in.labels(n);
    spec.labels.push_back({l.i(), l.j(), l.k()});
    for (int c : {l.i(), l.j(), l.k()}) {
      if (std::abs(static_cast<long long>(c)) < kMaxLabelComponent) continue;
      problems.push_back({path + ".labels[" + std::to_string(n) + "]", "components must lie within +-2^30"});
      in_range = false;
      break;
    }
  }
  return in_range;
}

// A field of another shape is a mistake (a radius on a rectangle means the shape is wrong).
void reject_other_shapes_fields(const v1::Body& in, const std::string& path, Problems& problems) {
  const std::string shape = v1::BodyShape_Name(in.shape());
  auto reject_unless = [&](bool set, v1::BodyShape owner, const char* field) {
    if (set && in.shape() != owner)
      problems.push_back({path + "." + field, "is only used by " + v1::BodyShape_Name(owner) + ", not " + shape});
  };
  reject_unless(in.size_size() > 0, v1::BODY_SHAPE_RECTANGLE, "size");
  reject_unless(in.radius() != 0, v1::BODY_SHAPE_DISK, "radius");
  reject_unless(in.length() != 0, v1::BODY_SHAPE_CHAIN, "length");
  reject_unless(in.axis() != v1::AXIS_UNSPECIFIED, v1::BODY_SHAPE_CHAIN, "axis");
  reject_unless(in.labels_size() > 0, v1::BODY_SHAPE_LABELS, "labels");
}

void translate_point_loads(const v1::Body& in, const std::string& path, int dimension, solid::BodySpec& spec,
                           Problems& problems) {
  if (in.point_loads_size() > kMaxBodyParticles) {
    problems.push_back({path + ".point_loads",
                        std::to_string(in.point_loads_size()) + " loads, more than the limit of 2^24 per body"});
    return;
  }
  for (int n = 0; n < in.point_loads_size(); ++n) {
    const v1::PointLoad& point = in.point_loads(n);
    if (!point.has_label()) {
      problems.push_back({path + ".point_loads[" + std::to_string(n) + "].label", "required"});
      continue;
    }
    const v1::Label& l = point.label();
    spec.point_loads.push_back({{l.i(), l.j(), l.k()}, vec(point.force(), dimension)});
  }
}

// Both thresholds optional, at least one set; each set one > 0 (0 would read as "off").
void translate_fracture(const v1::Fracture& in, const std::string& path, solid::BodySpec& spec, Problems& problems) {
  if (!in.has_max_force() && !in.has_max_stretch()) {
    problems.push_back({path, "give max_force, max_stretch or both"});
    return;
  }
  const auto threshold = [&](bool has, double value, const char* field, double& out) {
    if (!has) return;
    if (!(value > 0) || !std::isfinite(value))
      problems.push_back({path + "." + field, "must be a positive number, got " + number(value)});
    else out = value;
  };
  threshold(in.has_max_force(), in.max_force(), "max_force", spec.fracture.max_force);
  threshold(in.has_max_stretch(), in.max_stretch(), "max_stretch", spec.fracture.max_stretch);
}

TranslatedBody translate_body(const v1::Body& in, int index, int dimension, Problems& problems) {
  const std::string path = "scenario.bodies[" + std::to_string(index) + "]";
  TranslatedBody out;
  solid::BodySpec& spec = out.spec;
  spec.name = in.name().empty() ? "body" + std::to_string(index) : in.name();
  check_name(in.name(), path + ".name", problems);
  spec.spacing = in.has_spacing() ? in.spacing() : 1.0;
  spec.centre = vec(in.centre(), dimension);
  spec.velocity = vec(in.velocity(), dimension);
  spec.load = vec(in.load(), dimension);
  // All three components: a 2D body's x or y spin is refused by name (validate_body_spec).
  spec.angular_velocity = {in.angular_velocity().x(), in.angular_velocity().y(), in.angular_velocity().z()};
  spec.rotation = in.rotation();
  spec.anchored = in.anchored();
  if (in.anchor_labels_size() > kMaxBodyParticles) {
    problems.push_back({path + ".anchor_labels",
                        std::to_string(in.anchor_labels_size()) + " labels, more than the limit of 2^24 per body"});
  } else {
    for (int n = 0; n < in.anchor_labels_size(); ++n) {
      const v1::Label& l = in.anchor_labels(n);
      spec.anchor_labels.push_back({l.i(), l.j(), l.k()});
    }
  }
  translate_point_loads(in, path, dimension, spec, problems);
  if (in.has_fracture()) translate_fracture(in.fracture(), path + ".fracture", spec, problems);
  switch (in.shape()) {
    case v1::BODY_SHAPE_RECTANGLE:
      spec.shape = solid::BodyShape::kRectangle;
      out.core_can_check = translate_rectangle(in, path, dimension, spec, problems);
      break;
    case v1::BODY_SHAPE_DISK:
      spec.shape = solid::BodyShape::kDisk;
      out.core_can_check = translate_disk(in, path, dimension, spec, problems);
      break;
    case v1::BODY_SHAPE_CHAIN:
      spec.shape = solid::BodyShape::kChain;
      out.core_can_check = translate_chain(in, path, dimension, spec, problems);
      break;
    case v1::BODY_SHAPE_LABELS:
      spec.shape = solid::BodyShape::kLabels;
      out.core_can_check = translate_labels(in, path, spec, problems);
      break;
    case v1::BODY_SHAPE_UNSPECIFIED:
      problems.push_back({path + ".shape", "required (rectangle, disk, chain or labels)"});
      out.core_can_check = false;
      return out;
    default:
      problems.push_back({path + ".shape", unknown_enum(v1::BodyShape_descriptor(), in.shape())});
      out.core_can_check = false;
      return out;
  }
  reject_other_shapes_fields(in, path, problems);
  return out;
}

// ---- The rest of the message.

void translate_contact_and_exchange(const v1::Scenario& in, scene::Scene& out, Problems& problems) {
  const v1::Contact& c = in.contact();
  out.contact.enabled = !c.has_enabled() || c.enabled();
  out.contact.restitution = c.has_restitution() ? c.restitution() : 1.0;
  out.exchange = enum_or_report(exchange_of(in.exchange()), in.exchange(), v1::ExchangeRule_descriptor(),
                                "scenario.exchange", problems);
}

// The daemon always watches its runs: the API's interval is at least 1 (the core also allows 0, off).
// The density band is checked by the core (monitor.*), whose messages map to scenario.stability.*.
scene::MonitorSpec translate_stability(const v1::Stability& in, Problems& problems) {
  scene::MonitorSpec check;
  check.interval = in.has_check_interval() ? in.check_interval() : 100;
  check.limits.max_mach = in.has_max_mach() ? in.max_mach() : 0.5;
  if (in.has_min_density()) check.limits.min_density = in.min_density();
  if (in.has_max_density()) check.limits.max_density = in.max_density();
  if (check.interval < 1)
    problems.push_back(
        {"scenario.stability.check_interval", "must be at least 1, got " + std::to_string(check.interval)});
  if (!(check.limits.max_mach > 0) || !std::isfinite(check.limits.max_mach))
    problems.push_back(
        {"scenario.stability.max_mach", "must be a positive finite number, got " + number(check.limits.max_mach)});
  return check;
}

// Intervals above 2^40 steps would never be reached and could overflow the next frame's step.
constexpr long kMaxOutputInterval = 1L << 40;

OutputPlan translate_outputs(const v1::Scenario& in, const scene::Scene& scene, Problems& problems) {
  const v1::Outputs& o = in.outputs();
  OutputPlan plan;
  const auto interval = [&](long value, const char* field) {
    if (value < 0 || value > kMaxOutputInterval)
      problems.push_back({std::string("scenario.outputs.") + field,
                          "must lie in [0, 2^40] steps (0: none), got " + std::to_string(value)});
    return std::clamp(value, 0L, kMaxOutputInterval);
  };
  plan.particles_every = interval(o.particles_every(), "particles_every");
  plan.profile_every = interval(o.profile_every(), "profile_every");
  plan.fields_every = interval(o.fields_every(), "fields_every");
  plan.final_fields = o.final_fields();
  plan.checkpoint_every = interval(o.checkpoint_every(), "checkpoint_every");
  const bool fluid = scene.with_fluid;
  if (!fluid && (plan.profile_every > 0 || plan.fields_every > 0 || plan.final_fields))
    problems.push_back({"scenario.outputs", "velocity profiles and fields need a fluid (scenario.fluid.enabled)"});
  if (plan.particles_every > 0 && in.bodies_size() == 0)
    problems.push_back({"scenario.outputs.particles_every", "the scenario has no bodies"});
  std::unordered_set<std::string> names;
  for (const auto& body : in.bodies()) names.insert(body.name());
  for (int k = 0; k < o.particle_bodies_size(); ++k) {
    const std::string path = "scenario.outputs.particle_bodies[" + std::to_string(k) + "]";
    check_name(o.particle_bodies(k), path, problems);
    if (!names.count(o.particle_bodies(k))) problems.push_back({path, "no body of that name"});
  }
  if (o.particle_bodies_size() > 0 && plan.particles_every == 0)
    problems.push_back({"scenario.outputs.particle_bodies", "set particles_every to record them"});
  plan.particle_bodies.assign(o.particle_bodies().begin(), o.particle_bodies().end());
  return plan;
}

// ---- The core's errors, on proto paths.

Problem from_core(const std::string& message, const std::vector<int>& original) {
  const std::size_t colon = message.find(": ");
  const auto path = colon == std::string::npos ? std::nullopt : core_field_path(message.substr(0, colon), original);
  // A field this table does not know yet keeps the core's whole message rather than being lost.
  if (!path) return {"scenario", message};
  return {*path, message.substr(colon + 2)};
}

// Whether `path` continues below its first `size` characters ("scenario.domain" in
// "scenario.domain.nx", "scenario.bodies" in "scenario.bodies[3]").
bool field_ends_at(const std::string& path, std::size_t size) { return path[size] == '.' || path[size] == '['; }

// The core restates a message-level problem when it names the same field, a field that contains
// it (its "bodies: a scene without fluid needs a body" when a listed body could not be checked),
// or a field a covering problem stands for. The message-level paths are hashed with every field
// that contains them, so each core problem costs a few look-ups, not a pass over the others.
class Restatements {
 public:
  explicit Restatements(const Problems& message_level) {
    for (const Problem& p : message_level) {
      reported_or_containing_.insert(p.path);
      for (std::size_t size = 1; size < p.path.size(); ++size)
        if (field_ends_at(p.path, size)) reported_or_containing_.insert(p.path.substr(0, size));
      if (p.covers_subfields) covering_.insert(p.path);
    }
  }

  bool restated(const Problem& core) const {
    if (reported_or_containing_.count(core.path)) return true;
    for (std::size_t size = 1; size < core.path.size(); ++size)
      if (field_ends_at(core.path, size) && covering_.count(core.path.substr(0, size))) return true;
    return false;
  }

 private:
  std::unordered_set<std::string> reported_or_containing_, covering_;
};

// The copy the core checks: only the bodies it can list, and no arithmetic it would overflow.
scene::Scene checkable_copy(const scene::Scene& scene, const std::vector<bool>& core_can_check,
                            std::vector<int>& original) {
  scene::Scene copy = scene;
  copy.bodies.clear();
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    if (!core_can_check[b]) continue;
    solid::BodySpec spec = scene.bodies[b];
    // The core multiplies the extents in int. Positive extents were bounded in pass 1; with one
    // below 1 the product is unbounded, so every extent is squeezed into [0, 1]: the core, which
    // prints no extent, then reports the same problems without the overflow.
    if (std::any_of(spec.size.begin(), spec.size.end(), [](int extent) { return extent < 1; }))
      for (int& extent : spec.size) extent = std::clamp(extent, 0, 1);
    copy.bodies.push_back(spec);
    original.push_back(static_cast<int>(b));
  }
  // The core multiplies nx*ny*nz in 64 bits; a grid that large is already reported (over 2^31).
  fluid::FluidConfig& f = copy.fluid;
  if (static_cast<double>(f.nx) * f.ny * f.nz > 1e18) {
    for (int* n : {&f.nx, &f.ny, &f.nz}) *n = std::min(*n, 1 << 20);
  }
  return copy;
}

void add_core_problems(const scene::Scene& scene, const std::vector<bool>& core_can_check, Problems& problems) {
  std::vector<int> original;
  const scene::Scene copy = checkable_copy(scene, core_can_check, original);
  const Restatements message_level(problems);
  for (const std::string& message : scene::validate_scene(copy)) {
    Problem problem = from_core(message, original);
    if (!message_level.restated(problem)) problems.push_back(std::move(problem));
  }
}

// ---- Text.

class CollectErrors : public pb::io::ErrorCollector {
 public:
  void AddError(int line, pb::io::ColumnNumber column, const std::string& message) override {
    if (!text_.empty()) text_ += "; ";
    // protobuf counts from 0 (and gives -1 where it has no position).
    text_ += "line " + std::to_string(std::max(line, 0) + 1) + " column " + std::to_string(std::max(column, 0) + 1) +
             ": " + message;
  }
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

// The field a JsonStringToMessage error is about, as a dotted path: "(domain.nx): invalid value
// ...", "(domain) bogus: Cannot find field." or "bogus: Cannot find field."; empty when it names none.
std::string json_error_field(const std::string& message) {
  std::string parent, rest = message;
  if (message.starts_with("(")) {
    const std::size_t close = message.find(')');
    if (close == std::string::npos) return "";
    parent = message.substr(1, close - 1);
    rest = message.substr(close + 1);
    if (!rest.starts_with(" ")) return parent;  // "(domain.nx): ..." names the field itself
    rest.erase(0, 1);
  }
  const std::size_t colon = rest.find(':');
  const std::string name = colon == std::string::npos ? "" : rest.substr(0, colon);
  if (name.empty() || name.find_first_of(" \n") != std::string::npos) return parent;
  return parent.empty() ? name : parent + "." + name;
}

bool parse_json(const std::string& text, v1::Scenario* scenario, std::string* error) {
  json::Locator locator(text);
  if (!locator.check_syntax(error)) return false;
  pb::util::JsonParseOptions options;  // an unknown field is an error, as in text format
  const auto status = pb::util::JsonStringToMessage(text, scenario, options);
  if (status.ok()) return true;
  const std::string message(status.message());
  *error = locator.where(json_error_field(message)) + ": " + message;
  return false;
}

}  // namespace

// Fields this daemon does not know (a binary request from a newer client) would be ignored, and
// they cannot be written in the text form a checkpoint stores the scenario in: refused, by path.
static void report_unknown_fields(const pb::Message& message, const std::string& path, Problems& problems) {
  const pb::Reflection* reflection = message.GetReflection();
  const pb::UnknownFieldSet& unknown = reflection->GetUnknownFields(message);
  for (int k = 0; k < unknown.field_count(); ++k)
    problems.push_back({path, "field number " + std::to_string(unknown.field(k).number()) + " is not a field of " +
                                  message.GetDescriptor()->full_name() +
                                  " that this daemon knows (a newer client?); refused rather than ignored"});
  std::vector<const pb::FieldDescriptor*> fields;
  reflection->ListFields(message, &fields);
  for (const pb::FieldDescriptor* field : fields) {
    if (field->cpp_type() != pb::FieldDescriptor::CPPTYPE_MESSAGE) continue;
    const std::string field_path = path + "." + field->name();
    if (!field->is_repeated()) {
      report_unknown_fields(reflection->GetMessage(message, field), field_path, problems);
      continue;
    }
    for (int i = 0; i < reflection->FieldSize(message, field); ++i)
      report_unknown_fields(reflection->GetRepeatedMessage(message, field, i),
                            field_path + "[" + std::to_string(i) + "]", problems);
  }
}

TranslatedScenario translate_scenario(const lbsolid::v1::Scenario& in) {
  TranslatedScenario out;
  Problems problems;
  report_unknown_fields(in, "scenario", problems);
  check_name(in.name(), "scenario.name", problems);
  const std::optional<scene::LatticeKind> lattice = lattice_of(in.lattice());
  out.scene.lattice = enum_or_report(lattice, in.lattice(), v1::Lattice_descriptor(), "scenario.lattice", problems);
  const int dimension = lattice ? scene::lattice_dimension(*lattice) : 0;
  out.scene.precision = enum_or_report(precision_of(in.precision()), in.precision(), v1::Precision_descriptor(),
                                       "scenario.precision", problems);
  translate_domain(in, dimension, out.scene, problems);
  translate_fluid(in.fluid(), dimension, out.scene, problems);
  std::vector<bool> core_can_check;
  for (int b = 0; b < in.bodies_size(); ++b) {
    TranslatedBody body = translate_body(in.bodies(b), b, dimension, problems);
    out.scene.bodies.push_back(std::move(body.spec));
    core_can_check.push_back(body.core_can_check);
  }
  translate_contact_and_exchange(in, out.scene, problems);
  out.scene.monitor = translate_stability(in.stability(), problems);
  out.outputs = translate_outputs(in, out.scene, problems);
  // With no lattice the core checks nothing but the lattice, which is already reported.
  if (lattice) add_core_problems(out.scene, core_can_check, problems);
  // The core repeats a message once per offending axis ("size: every extent must be at least 1").
  // The views point into out.errors, which the reserve keeps from moving.
  out.errors.reserve(problems.size());
  std::unordered_set<std::string_view> seen(2 * problems.size());
  for (const Problem& p : problems) {
    std::string text = p.path + ": " + p.reason;
    if (seen.count(text)) continue;
    out.errors.push_back(std::move(text));
    seen.insert(out.errors.back());
  }
  // Parameters near the edge of stability, on their proto paths; only for a scene that can run.
  if (out.errors.empty()) {
    std::vector<int> identity(out.scene.bodies.size());
    for (std::size_t b = 0; b < identity.size(); ++b) identity[b] = static_cast<int>(b);
    for (const std::string& warning : scene::scene_warnings(out.scene)) {
      const Problem p = from_core(warning, identity);
      out.warnings.push_back(p.path + ": " + p.reason);
    }
  }
  return out;
}

bool parse_scenario_text(const std::string& text, lbsolid::v1::Scenario* scenario, std::string* error) {
  scenario->Clear();
  std::string ignored;
  if (!error) error = &ignored;
  const std::size_t first = text.find_first_not_of(" \t\r\n\f\v");
  bool parsed;
  if (first != std::string::npos && text[first] == '{') {
    parsed = parse_json(text, scenario, error);
  } else {
    CollectErrors errors;
    pb::TextFormat::Parser parser;
    parser.RecordErrorsTo(&errors);
    parsed = parser.ParseFromString(text, scenario);
    if (!parsed)
      *error = errors.text().empty() ? "line 1 column 1: not a scenario in protobuf text format" : errors.text();
  }
  // A half-read scenario is of no use to anyone; leave nothing behind.
  if (!parsed) scenario->Clear();
  return parsed;
}

std::string scenario_to_text(const lbsolid::v1::Scenario& scenario) {
  std::string text;
  pb::TextFormat::PrintToString(scenario, &text);
  return text;
}

}  // namespace lbsolid::server
