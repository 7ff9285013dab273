#pragma once
// What the exchange stage leaves for the fluid and solid stages of the same step: the exchange
// itself (each particle's node and u*, each node's gain) and, for rotating bodies, the momenta the
// exchange compared at each particle's node.
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "coupling/momentum_exchange.h"
#include "coupling/node_locator.h"
#include "scene/scene.h"
#include "solid/solid_system.h"

namespace lbsolid::scene {

struct CouplingState {
  CouplingState(const Scene& scene, int particles, bool rotating)
      : exchange(std::array<int, 3>{scene.fluid.nx, scene.fluid.ny, scene.fluid.nz}, scene.exchange),
        rotating(rotating) {
    if (rotating) node.resize(particles);
  }
  std::size_t bytes_allocated() const {
    return exchange.bytes_allocated() + node.capacity() * sizeof(coupling::Node) +
           momenta_at_nodes.capacity() * sizeof(double);
  }

  coupling::MomentumExchange exchange;
  bool rotating;                          // some body's springs turn with it
  // The fluid is read and given its momentum inside its step (MomentumExchange::step_fluid)
  // rather than before and after it: where the fluid and the rule allow (set by the simulation).
  bool in_step = false;
  std::vector<coupling::Node> node;       // rotating: each particle's node, from the last locate
  std::vector<double> momenta_at_nodes;   // rotating: what the exchange compared, as the solid stores vectors
  // Without rotating bodies, the solid's step finds each particle's next node as it stores the
  // particle's new position (NextNodes), and the next exchange stage need not locate while the
  // positions are those (the solid's positions_version() equals located_version; 0: none).
  // nearest_cells is NodeLocator::nearest_cells on the scene's lattice.
  std::function<void(const double* positions, long first, long end, coupling::CellIndex* cells)> nearest_cells;
  std::uint64_t located_version = 0;
};

// For SolidSystem::stream: each range of the solid's step locates its particles' nodes a block
// at a time, while their new positions are in the cache (a separate pass read them all again:
// 16 B a particle in 2D, from memory in a large solid). Call exchange.begin_locate() first.
struct NextNodes {
  CouplingState& coupling;
  const double* positions;  // the solid's, which the step updates in place
  struct Range {
    coupling::MomentumExchange::RangeLocator locator;
    const NextNodes* of;
    void operator()(int first, int end) {
      locator(first, end, [this](long from, long to, coupling::CellIndex* cells) {
        of->coupling.nearest_cells(of->positions, from, to, cells);
      });
    }
    void finish() { locator.finish(); }
  };
  Range range() const { return {coupling::MomentumExchange::RangeLocator(coupling.exchange), this}; }
};

}  // namespace lbsolid::scene
