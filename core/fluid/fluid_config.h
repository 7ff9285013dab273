#pragma once
// What a fluid is made of: grid size, relaxation, reference density, a boundary per side and a
// uniform body force. Plain data; validate_fluid_config() says what is wrong with it, field by field.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "fluid/population_storage.h"

namespace lbsolid::fluid {

using Vec3 = std::array<double, 3>;

enum class WallKind {
  kPeriodic,    // wraps to the opposite side (both sides of an axis must be periodic)
  kBounceBack,  // half-way bounce-back: no-slip wall at rest
  kMovingWall,  // Ladd's moving wall: no-slip wall moving at wall_velocity
  kFreeSlip,    // specular reflection; `traction` is a tangential force per unit wall length
  // Open sides (x sides only, every lattice; pull_source.h gives the rules):
  kVelocityInlet,   // fluid enters at `inflow_speed` with `inflow_profile` (Ladd's rule, as a moving wall)
  kPressureOutlet,  // fluid leaves where the density is held at `outflow_density` (equilibrium inflow)
};

// How the speed of a velocity inlet varies across it.
enum class InflowProfile {
  kUniform,    // inflow_speed everywhere
  kParabolic,  // inflow_speed times 4 s (1 - s) across each transverse axis that has walls,
               // s the position between its walls (half-way: s = (y + 1/2) / ny); the peak is inflow_speed
};

const char* wall_kind_name(WallKind kind);

struct SideBoundary {
  WallKind kind = WallKind::kPeriodic;
  Vec3 wall_velocity{0, 0, 0};  // kMovingWall only: tangential velocity, lattice units per step
  Vec3 traction{0, 0, 0};       // kFreeSlip only: tangential stress on the adjacent fluid layer
  double inflow_speed = 0;      // kVelocityInlet only: speed into the box (peak of a parabolic profile)
  InflowProfile inflow_profile = InflowProfile::kUniform;  // kVelocityInlet only
  double outflow_density = 0;   // kPressureOutlet only: the density held there; 0 means rho0
};

bool is_open(WallKind kind);
const char* inflow_profile_name(InflowProfile profile);
struct FluidConfig;
// The speed into the box at the node of row (y, z) on velocity inlet `side` (an x side).
double inflow_speed_at(const FluidConfig& config, int side, int y, int z);

enum class StreamingScheme {
  kInPlace,    // one buffer, AA pattern: half the memory, each cell reads and writes the same slots
  kTwoBuffer,  // two buffers, pull from one and write the other
};

// The collision operator (MODEL.md uses BGK, the paper's).
enum class CollisionModel {
  kBgk,          // single relaxation time omega
  kTrt,          // two relaxation times: omega for the symmetric part, omega_minus for the
                 // antisymmetric one, set by the magic parameter Lambda = (1/omega - 1/2)(1/omega_minus - 1/2)
  kRegularized,  // BGK on the populations rebuilt from rho, u and the non-equilibrium stress
};

const char* collision_model_name(CollisionModel model);

// Sides in the order x_low, x_high, y_low, y_high, z_low, z_high.
enum Side { kXLow = 0, kXHigh, kYLow, kYHigh, kZLow, kZHigh };
const char* side_name(int side);

struct FluidConfig {
  int nx = 1, ny = 1, nz = 1;  // nodes per axis (nz = 1 in 2D)
  double omega = 1.0;          // relaxation rate (TRT: of the even part), in (0, 2)
  double rho0 = 1.0;           // reference density: storage offset and moving-wall density
  std::array<SideBoundary, 6> sides{};
  Vec3 body_force{0, 0, 0};  // force per node (momentum added per node per step)
  int threads = 1;           // parts each step is cut into: the threads of its own pool, or parts for a shared one
  StreamingScheme streaming = StreamingScheme::kInPlace;
  CollisionModel collision = CollisionModel::kBgk;
  double trt_magic = 3.0 / 16.0;  // TRT's Lambda: 3/16 puts bounce-back walls exactly half-way (Poiseuille)
  // How the populations are stored (population_storage.h); unset, the lattice chooses
  // (FluidLattice::chosen_layout). Blocks need D3Q19, in-place streaming, BGK, every side
  // periodic and n_x a multiple of 8 (double) or 16 (float). The results are the same bit for bit.
  std::optional<PopulationLayout> layout;
};

// Every problem with `config` for a lattice of dimension `dimension`, each as
// "<field>: <reason>". Empty when the configuration can run.
std::vector<std::string> validate_fluid_config(const FluidConfig& config, int dimension,
                                               bool hexagonal);

}  // namespace lbsolid::fluid
