#include "server/session/footprint.h"

#include "coupling/momentum_exchange.h"
#include "fluid/row_plan.h"
#include "server/session/session.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lbsolid::server {

namespace {

namespace v1 = ::lbsolid::v1;

// Low enough that two saturated figures, or a daemon total plus one, still fit in a long long.
constexpr long long kSaturated = 1LL << 60;

long long saturating_product(long long a, long long b) {
  if (a <= 0 || b <= 0) return 0;
  return a > kSaturated / b ? kSaturated : a * b;
}
long long saturating_sum(long long a, long long b) { return std::min(kSaturated, a + b); }

int dimension_of(v1::Lattice lattice) { return lattice == v1::LATTICE_D3Q19 ? 3 : 2; }

int velocities_of(v1::Lattice lattice) {
  switch (lattice) {
    case v1::LATTICE_D2Q7: return 7;
    case v1::LATTICE_D3Q19: return 19;
    default: return 9;
  }
}

// Particles of one body, an upper bound (a disk counts its bounding square or cube).
long long particles_of(const v1::Body& body, int dimension) {
  switch (body.shape()) {
    case v1::BODY_SHAPE_RECTANGLE: {
      long long n = 1;
      for (int a = 0; a < std::min(body.size_size(), dimension); ++a) n = saturating_product(n, body.size(a));
      return body.size_size() == 0 ? 0 : n;
    }
    case v1::BODY_SHAPE_DISK: {
      if (!(body.radius() > 0)) return 0;
      const double side = 2 * std::floor(std::min(body.radius(), 1e9)) + 1;
      long long n = 1;
      for (int a = 0; a < dimension; ++a) n = saturating_product(n, static_cast<long long>(side));
      return n;
    }
    case v1::BODY_SHAPE_CHAIN: return std::max(0, body.length());
    case v1::BODY_SHAPE_LABELS: return body.labels_size();
    default: return 0;
  }
}

// Bytes per particle in SolidSystem and, with a fluid, in the exchange (scene/simulation.cpp,
// coupling/momentum_exchange.h). The solid's vectors hold `dimension` doubles
// (solid/particle_vectors.h): body index 4, label 12, position, mass 8, momentum, the step's base
// vector, per link a neighbour index 4 and a vector, an anchor flag 1 and the anchor record's 24
// (scene/stages/anchor_record.h; counted whether or not a body is anchored: the estimate errs
// high); exchange: cell 4, slot 4, its place in the parts' order 4, a node record of 120 (at
// most one node per particle), the pairwise rule's density 8 a node and dP 24, and with rotating
// bodies each particle's node 12 and the momenta compared at the nodes; with rotating bodies, the torque record's 48 (scene/stages/torque_record.h); with
// point loads or a breaking body, the particle forces' 2 x 24 and a touched index 4
// (scene/stages/particle_forces.h), the fracture test's mask 1 and at most `dimension` broken
// links of 40 (solid::BrokenLink) a particle.
// Doubled: arrays grown by push_back or resize may hold up to twice their size.
long long bytes_per_particle(int dimension, bool with_fluid, bool rotating, bool particle_forces) {
  const int links = 2 * dimension;
  const int vector = 8 * dimension;
  const long long solid = 4 + 12 + vector + 8 + vector + vector + links * (4 + vector) + 1 + 24;
  // The exchange: a particle's cell, slot and place in order_, its node's slot (120 B), its
  // mass, its pairwise dP; for the listing kept between exchanges, its listed cell and up to
  // 1/16 more slots (7.5 B) with their table's entries (1 B) and noted moves (0.25 B): 16 B.
  static_assert(coupling::MomentumExchange::kRelistDivisor >= 16, "the kept listing's 16 B a particle");
  const long long exchange = with_fluid ? 4 + 4 + 4 + 120 + 8 + 24 + 16 + (rotating ? 12 + vector : 0) : 0;
  const long long torque = rotating ? 48 : 0;
  const long long forces = particle_forces ? 2 * 24 + 4 + 1 + dimension * 40 : 0;
  return 2 * (solid + exchange + torque + forces);
}

// One population array (fluid/population_storage.h): the cells rounded up to 64 KiB, plus 17
// cache lines of offset.
long long population_array_bytes(long long cells, int value_bytes) {
  return saturating_sum(saturating_product(cells, value_bytes), (64 << 10) + 17 * 64);
}

}  // namespace

Footprint& Footprint::operator+=(const Footprint& o) {
  cells += o.cells;
  particles += o.particles;
  resident_bytes += o.resident_bytes;
  transient_bytes += o.transient_bytes;
  return *this;
}

Footprint& Footprint::operator-=(const Footprint& o) {
  cells -= o.cells;
  particles -= o.particles;
  resident_bytes -= o.resident_bytes;
  transient_bytes -= o.transient_bytes;
  return *this;
}

Footprint estimate_footprint(const v1::Scenario& scenario) {
  Footprint f;
  const int dimension = dimension_of(scenario.lattice());
  const bool with_fluid = !scenario.fluid().has_enabled() || scenario.fluid().enabled();
  const auto& d = scenario.domain();
  const long long nz = d.has_nz() ? d.nz() : 1;
  if (with_fluid) f.cells = saturating_product(saturating_product(std::max(0, d.nx()), std::max(0, d.ny())), nz);
  for (const auto& body : scenario.bodies()) f.particles = saturating_sum(f.particles, particles_of(body, dimension));

  const int q = velocities_of(scenario.lattice());
  const int buffers = scenario.fluid().streaming() == v1::STREAMING_TWO_BUFFER ? 2 : 1;
  const int value_bytes = scenario.precision() == v1::PRECISION_FLOAT ? 4 : 8;
  const long long populations = saturating_product(buffers * q, population_array_bytes(f.cells, value_bytes));
  // The exchange's marks (16 B a word of 64 cells: a quarter of a byte a cell, one word more
  // for the last cells), the marks of the nodes listed since a listing (a bit a cell, once a
  // particle moves to a node not listed), its balancing counts and the fluid's count of each
  // row's nodes (4 B a row).
  constexpr long long kBalanceBytes = (coupling::MomentumExchange::kBalanceBlocks + 1) * sizeof(long);
  const long long rows = with_fluid ? saturating_product(std::max(0, d.ny()), nz) : 0;
  const long long exchange_cells =
      f.particles > 0
          ? saturating_sum(saturating_sum(f.cells / 4 + 16 + f.cells / 8 + 8, kBalanceBytes), saturating_product(rows, 4))
          : 0;
  const bool rotating = std::any_of(scenario.bodies().begin(), scenario.bodies().end(),
                                    [](const v1::Body& body) { return body.rotation(); });
  const bool particle_forces = std::any_of(scenario.bodies().begin(), scenario.bodies().end(), [](const v1::Body& body) {
    return body.point_loads_size() > 0 || body.has_fracture();
  });
  const long long solid =
      saturating_product(f.particles, bytes_per_particle(dimension, with_fluid, rotating, particle_forces));
  // Open x sides give the first and last cell of every row sources of their own (fluid/row_plan.h):
  // Q of them a cell.
  auto open = [](const v1::Side& side) {
    return side.kind() == v1::WALL_KIND_VELOCITY_INLET || side.kind() == v1::WALL_KIND_PRESSURE_OUTLET;
  };
  const long long edge_sources =
      with_fluid && (open(d.x_low()) || open(d.x_high()))
          ? saturating_product(saturating_product(std::max(0, d.ny()), nz), 2 * q * static_cast<long long>(value_bytes == 8 ? sizeof(fluid::PullSource<double, 1>)
                                                                                     : sizeof(fluid::PullSource<float, 1>)))
          : 0;
  f.resident_bytes = saturating_sum(saturating_sum(saturating_sum(populations, exchange_cells), solid), edge_sources);

  // A save copies the populations as doubles and the solid's positions, links and momenta; field
  // reads copy density and velocity (4 doubles a node), Session::kFieldSnapshots copies at most.
  const long long saved_fluid = saturating_product(saturating_product(f.cells, buffers * q), 8);
  const long long saved_solid = saturating_product(f.particles, 24 + 24 * 2 * dimension + 24);
  const long long field_read = saturating_product(f.cells, 32 * Session::kFieldSnapshots);
  f.transient_bytes = saturating_sum(saturating_sum(saved_fluid, saved_solid), field_read);
  return f;
}

}  // namespace lbsolid::server
