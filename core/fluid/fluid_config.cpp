#include "fluid/fluid_config.h"

#include <cmath>
#include <string>

namespace lbsolid::fluid {

const char* wall_kind_name(WallKind kind) {
  switch (kind) {
    case WallKind::kPeriodic: return "periodic";
    case WallKind::kBounceBack: return "bounce-back";
    case WallKind::kMovingWall: return "moving wall";
    case WallKind::kFreeSlip: return "free-slip";
    case WallKind::kVelocityInlet: return "velocity inlet";
    case WallKind::kPressureOutlet: return "pressure outlet";
  }
  return "unknown";
}

bool is_open(WallKind kind) { return kind == WallKind::kVelocityInlet || kind == WallKind::kPressureOutlet; }

const char* inflow_profile_name(InflowProfile profile) {
  switch (profile) {
    case InflowProfile::kUniform: return "uniform";
    case InflowProfile::kParabolic: return "parabolic";
  }
  return "unknown";
}

double inflow_speed_at(const FluidConfig& config, int side, int y, int z) {
  const SideBoundary& inlet = config.sides[side];
  double speed = inlet.inflow_speed;
  if (inlet.inflow_profile != InflowProfile::kParabolic) return speed;
  // Each transverse axis with walls shapes the profile; the walls sit half-way beyond the end nodes.
  auto across = [&](int low_side, int at, int n) {
    if (config.sides[low_side].kind == WallKind::kPeriodic) return;
    const double s = (at + 0.5) / n;
    speed *= 4.0 * s * (1.0 - s);
  };
  across(kYLow, y, config.ny);
  across(kZLow, z, config.nz);  // periodic in 2D
  return speed;
}

const char* collision_model_name(CollisionModel model) {
  switch (model) {
    case CollisionModel::kBgk: return "bgk";
    case CollisionModel::kTrt: return "trt";
    case CollisionModel::kRegularized: return "regularized";
  }
  return "unknown";
}

const char* side_name(int side) {
  static constexpr const char* names[6] = {"x_low", "x_high", "y_low", "y_high", "z_low", "z_high"};
  return side >= 0 && side < 6 ? names[side] : "unknown";
}

namespace {

bool finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

// The most cells a grid may have: a cell index then fits 32 bits (the coupling keeps one per
// particle, coupling::CellIndex), and a fluid this large (120 GB in D2Q7 float) is beyond memory
// anyway.
constexpr long long kMaxCells = (1LL << 32) - 1;

// An open side's own fields, and that other sides leave them alone.
template <class Error>
void check_open_side(const SideBoundary& b, int side, const std::string& field, const Error& error) {
  if (is_open(b.kind) && side / 2 != 0) error(field, std::string(wall_kind_name(b.kind)) + "s are supported on x sides only");
  // Speeds and densities against the stability monitor's limits: scene.cpp, as for moving walls.
  if (!std::isfinite(b.inflow_speed)) {
    error(field + ".inflow_speed", "must be finite");
  } else if (b.kind != WallKind::kVelocityInlet && b.inflow_speed != 0.0) {
    error(field + ".inflow_speed", std::string("is only used by a velocity inlet, not a ") + wall_kind_name(b.kind) + " side");
  }
  if (b.inflow_profile != InflowProfile::kUniform && b.inflow_profile != InflowProfile::kParabolic) {
    error(field + ".inflow_profile", "unknown profile " + std::to_string(static_cast<int>(b.inflow_profile)));
  } else if (b.kind != WallKind::kVelocityInlet && b.inflow_profile != InflowProfile::kUniform) {
    error(field + ".inflow_profile", std::string("is only used by a velocity inlet, not a ") + wall_kind_name(b.kind) + " side");
  }
  if (!std::isfinite(b.outflow_density) || b.outflow_density < 0.0) {
    error(field + ".outflow_density", "must be a positive finite density");
  } else if (b.kind != WallKind::kPressureOutlet && b.outflow_density != 0.0) {
    error(field + ".outflow_density", std::string("is only used by a pressure outlet, not a ") + wall_kind_name(b.kind) + " side");
  }
}

}  // namespace

std::vector<std::string> validate_fluid_config(const FluidConfig& config, int dimension,
                                               bool hexagonal) {
  std::vector<std::string> errors;
  auto error = [&](const std::string& field, const std::string& reason) {
    errors.push_back(field + ": " + reason);
  };
  const int n[3] = {config.nx, config.ny, config.nz};
  const char* axis_field[3] = {"nx", "ny", "nz"};
  for (int a = 0; a < 3; ++a) {
    if (n[a] < 1) error(axis_field[a], "must be at least 1, got " + std::to_string(n[a]));
  }
  if (dimension == 2 && config.nz != 1) {
    error("nz", "must be 1 on a 2D lattice, got " + std::to_string(config.nz));
  }
  if (errors.empty() && static_cast<long long>(config.nx) * config.ny * config.nz > kMaxCells) {
    error("nx*ny*nz", "grid of " +
                          std::to_string(static_cast<long long>(config.nx) * config.ny * config.nz) +
                          " cells exceeds the limit of " + std::to_string(kMaxCells));
  }
  if (!(config.omega > 0.0 && config.omega < 2.0)) {
    error("omega", "must lie in (0, 2) for a stable, positive viscosity, got " +
                       std::to_string(config.omega));
  }
  if (!(config.rho0 > 0.0) || !std::isfinite(config.rho0)) {
    error("rho0", "must be a positive finite density, got " + std::to_string(config.rho0));
  }
  if (!finite(config.body_force)) error("body_force", "must be finite");
  if (config.threads < 1) {
    error("threads", "must be at least 1, got " + std::to_string(config.threads));
  }
  if (config.streaming != StreamingScheme::kInPlace && config.streaming != StreamingScheme::kTwoBuffer) {
    error("streaming", "unknown scheme " + std::to_string(static_cast<int>(config.streaming)) +
                           "; use in-place or two-buffer");
  }
  if (config.collision != CollisionModel::kBgk && config.collision != CollisionModel::kTrt &&
      config.collision != CollisionModel::kRegularized) {
    error("collision", "unknown model " + std::to_string(static_cast<int>(config.collision)) +
                           "; use bgk, trt or regularized");
  }
  // Checked whatever the model, so that a scene switching to TRT later cannot carry a bad value.
  if (!(config.trt_magic > 0.0) || !std::isfinite(config.trt_magic)) {
    error("trt_magic", "must be positive, got " + std::to_string(config.trt_magic));
  }
  const int axes = dimension;
  for (int side = 0; side < 6; ++side) {
    const SideBoundary& b = config.sides[side];
    const int axis = side / 2;
    const std::string field = std::string("sides.") + side_name(side);
    if (b.kind != WallKind::kPeriodic && b.kind != WallKind::kBounceBack && b.kind != WallKind::kMovingWall &&
        b.kind != WallKind::kFreeSlip && !is_open(b.kind)) {
      error(field, "unknown wall kind " + std::to_string(static_cast<int>(b.kind)));
      continue;
    }
    if (axis >= axes) {
      if (b.kind != WallKind::kPeriodic) error(field, "a 2D lattice has no z walls; use periodic");
      continue;
    }
    if (!finite(b.wall_velocity)) error(field + ".wall_velocity", "must be finite");
    if (!finite(b.traction)) error(field + ".traction", "must be finite");
    if (b.kind == WallKind::kMovingWall && b.wall_velocity[axis] != 0.0) {
      error(field + ".wall_velocity", "must be tangential to the wall (zero along its normal)");
    }
    if (b.kind == WallKind::kFreeSlip) {
      if (axis == 0) error(field, "free-slip walls are supported on y and z sides only");
      if (b.traction[axis] != 0.0) {
        error(field + ".traction", "must be tangential to the wall (zero along its normal)");
      }
    }
    if (b.kind != WallKind::kMovingWall && (b.wall_velocity[0] != 0.0 || b.wall_velocity[1] != 0.0 ||
                                            b.wall_velocity[2] != 0.0)) {
      error(field + ".wall_velocity", std::string("is only used by a moving wall, not a ") +
                                          wall_kind_name(b.kind) + " side");
    }
    if (b.kind != WallKind::kFreeSlip &&
        (b.traction[0] != 0.0 || b.traction[1] != 0.0 || b.traction[2] != 0.0)) {
      error(field + ".traction", std::string("is only used by a free-slip wall, not a ") +
                                     wall_kind_name(b.kind) + " side");
    }
    check_open_side(b, side, field, error);
  }
  for (int axis = 0; axis < axes; ++axis) {
    const bool low = config.sides[2 * axis].kind == WallKind::kPeriodic;
    const bool high = config.sides[2 * axis + 1].kind == WallKind::kPeriodic;
    if (low != high) {
      error(std::string("sides.") + side_name(2 * axis),
            std::string("periodic must be set on both ") + side_name(2 * axis) + " and " +
                side_name(2 * axis + 1));
    }
  }
  if (hexagonal && config.sides[kYLow].kind == WallKind::kPeriodic && config.ny % 2 != 0) {
    error("ny", "a hexagonal (D2Q7) lattice periodic in y needs an even ny, got " +
                    std::to_string(config.ny));
  }
  return errors;
}

}  // namespace lbsolid::fluid
