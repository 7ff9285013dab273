#pragma once
// What the exchange stage leaves for the fluid and solid stages of the same step: the exchange
// itself (each particle's node and u*, each node's gain) and, for rotating bodies, the momenta the
// exchange compared at each particle's node.
#include <array>
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
};

}  // namespace lbsolid::scene
