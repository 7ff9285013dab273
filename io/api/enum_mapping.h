#pragma once
// Every value of the API's enums (proto/lbsolid/v1/scenario.proto) and its core counterpart.
// UNSPECIFIED means the default scenario.proto documents for the field; nullopt is a number the
// proto does not define (proto3 keeps unknown numbers), for the caller to report. BodyShape is
// mapped where bodies are translated: its UNSPECIFIED is an error, not a default. Internal to
// scenario_translation.cpp; header-only because the API library is a single translation unit.
#include <optional>

#include "lbsolid/v1/scenario.pb.h"
#include "scene/scene.h"

namespace lbsolid::server {

inline std::optional<scene::LatticeKind> lattice_of(lbsolid::v1::Lattice value) {
  switch (value) {
    case lbsolid::v1::LATTICE_UNSPECIFIED:
    case lbsolid::v1::LATTICE_D2Q9: return scene::LatticeKind::kD2Q9;
    case lbsolid::v1::LATTICE_D2Q7: return scene::LatticeKind::kD2Q7;
    case lbsolid::v1::LATTICE_D3Q19: return scene::LatticeKind::kD3Q19;
    default: return std::nullopt;
  }
}

inline std::optional<scene::Precision> precision_of(lbsolid::v1::Precision value) {
  switch (value) {
    case lbsolid::v1::PRECISION_UNSPECIFIED:
    case lbsolid::v1::PRECISION_DOUBLE: return scene::Precision::kDouble;
    case lbsolid::v1::PRECISION_FLOAT: return scene::Precision::kFloat;
    default: return std::nullopt;
  }
}

inline std::optional<fluid::WallKind> wall_kind_of(lbsolid::v1::WallKind value) {
  switch (value) {
    case lbsolid::v1::WALL_KIND_UNSPECIFIED:
    case lbsolid::v1::WALL_KIND_PERIODIC: return fluid::WallKind::kPeriodic;
    case lbsolid::v1::WALL_KIND_BOUNCE_BACK: return fluid::WallKind::kBounceBack;
    case lbsolid::v1::WALL_KIND_MOVING_WALL: return fluid::WallKind::kMovingWall;
    case lbsolid::v1::WALL_KIND_FREE_SLIP: return fluid::WallKind::kFreeSlip;
    case lbsolid::v1::WALL_KIND_VELOCITY_INLET: return fluid::WallKind::kVelocityInlet;
    case lbsolid::v1::WALL_KIND_PRESSURE_OUTLET: return fluid::WallKind::kPressureOutlet;
    default: return std::nullopt;
  }
}

inline std::optional<fluid::InflowProfile> inflow_profile_of(lbsolid::v1::InflowProfile value) {
  switch (value) {
    case lbsolid::v1::INFLOW_PROFILE_UNSPECIFIED:
    case lbsolid::v1::INFLOW_PROFILE_UNIFORM: return fluid::InflowProfile::kUniform;
    case lbsolid::v1::INFLOW_PROFILE_PARABOLIC: return fluid::InflowProfile::kParabolic;
    default: return std::nullopt;
  }
}

inline std::optional<fluid::StreamingScheme> streaming_of(lbsolid::v1::Streaming value) {
  switch (value) {
    case lbsolid::v1::STREAMING_UNSPECIFIED:
    case lbsolid::v1::STREAMING_IN_PLACE: return fluid::StreamingScheme::kInPlace;
    case lbsolid::v1::STREAMING_TWO_BUFFER: return fluid::StreamingScheme::kTwoBuffer;
    default: return std::nullopt;
  }
}

inline std::optional<fluid::CollisionModel> collision_of(lbsolid::v1::Collision value) {
  switch (value) {
    case lbsolid::v1::COLLISION_UNSPECIFIED:
    case lbsolid::v1::COLLISION_BGK: return fluid::CollisionModel::kBgk;
    case lbsolid::v1::COLLISION_TRT: return fluid::CollisionModel::kTrt;
    case lbsolid::v1::COLLISION_REGULARIZED: return fluid::CollisionModel::kRegularized;
    default: return std::nullopt;
  }
}

inline std::optional<coupling::ExchangeRule> exchange_of(lbsolid::v1::ExchangeRule value) {
  switch (value) {
    case lbsolid::v1::EXCHANGE_RULE_UNSPECIFIED:
    case lbsolid::v1::EXCHANGE_RULE_COMMON_VELOCITY: return coupling::ExchangeRule::kCommonVelocity;
    case lbsolid::v1::EXCHANGE_RULE_PAIRWISE: return coupling::ExchangeRule::kPairwise;
    default: return std::nullopt;
  }
}

// The core axis (0, 1, 2) of a proto Axis.
inline std::optional<int> axis_of(lbsolid::v1::Axis value) {
  switch (value) {
    case lbsolid::v1::AXIS_UNSPECIFIED:
    case lbsolid::v1::AXIS_X: return 0;
    case lbsolid::v1::AXIS_Y: return 1;
    case lbsolid::v1::AXIS_Z: return 2;
    default: return std::nullopt;
  }
}

}  // namespace lbsolid::server
