#pragma once
// The per-node momentum exchange (MODEL.md section 3). Every particle is attached to its nearest
// fluid node; at each node the fluid and all the particles there reach one common velocity
//   u* = (rho u_f + sum_p M_p u_p) / (rho + sum_p M_p),   dP_p = M_p (u_p - u*),
// which for a lone particle is exactly eq. 14, dP = Z (u_s - u_f) with 1/Z = 1/rho + 1/M.
// The pairwise rule (eq. 14 applied to each particle against the same fluid state) is kept only
// to show why it is not used: with several particles on a node it over-corrects and can diverge.
#include <vector>

#include "coupling/node_locator.h"
#include "fluid/node_exchange_types.h"
#include "parallel/thread_pool.h"

namespace lbsolid::coupling {

enum class ExchangeRule { kCommonVelocity, kPairwise };
const char* exchange_rule_name(ExchangeRule rule);

// The nodes an exchange touched and the momentum each node's fluid gains, index for index.
struct ExchangedNodes {
  std::vector<Node> nodes;
  std::vector<fluid::Vec3> gained;
  long size() const { return static_cast<long>(nodes.size()); }
};

class MomentumExchange {
 public:
  // On a grid of nx x ny x nz fluid nodes.
  MomentumExchange(const std::array<int, 3>& grid, ExchangeRule rule);

  // `node[p]`, `cell[p]`, `mass[p]`, `momentum[p]` describe particle p; `fluid` answers
  // gather_momenta(nodes, count, out) with the pre-collision density and momentum of each node
  // (FluidLattice's batched call). Fills `particle_dp` (momentum each particle gives) and keeps
  // what each node's fluid gains for inject().
  //
  // The particles are sorted by fluid row (a stable counting sort, in the same parts); then the rows
  // are independent: with a pool they are cut into `parts` ranges of about equal particle counts
  // run on it, each row grouping its particles by node (in a per-cell list no other row touches),
  // reading its nodes' fluid in one batch and exchanging, so that the fluid is read, and later written, a row at a time. Within a
  // row the nodes come in the order of their first particle, and a node's particles in descending
  // order: the result is the same bit for bit for any number of parts. `fluid` must then allow
  // several threads to gather at once (a const read).
  template <class Fluid>
  void compute(const std::vector<Node>& node, const std::vector<long>& cell, const std::vector<double>& mass,
               const std::vector<fluid::Vec3>& momentum, const Fluid& fluid, std::vector<fluid::Vec3>& particle_dp,
               parallel::ThreadPool* pool = nullptr, int parts = 1);
  // Gives the fluid the momentum of the last compute() (fluid.add_momenta per row), in the same
  // parts: each node's slots are written by no other node. Call after the fluid's step.
  template <class Fluid>
  void inject(Fluid& fluid, parallel::ThreadPool* pool = nullptr, int parts = 1) const;

  // The last compute()'s nodes and what their fluid gains, row by row (tests, diagnostics).
  ExchangedNodes exchanged() const;
  ExchangeRule rule() const { return rule_; }
  std::size_t bytes_allocated() const;

 private:
  void sort_by_row(const std::vector<Node>& node, parallel::ThreadPool* pool, int parts);
  // Groups row r's particles by node, and lists its nodes at slots from row_start_[r] on.
  void group_row(long r, const std::vector<Node>& node, const std::vector<long>& cell);
  // The exchange at one listed node, its fluid being `f`.
  void exchange_at(long slot, const fluid::DensityMomentum& f, const std::vector<double>& mass,
                   const std::vector<fluid::Vec3>& momentum, std::vector<fluid::Vec3>& particle_dp);
  template <class Rows>
  void for_rows(parallel::ThreadPool* pool, int parts, const Rows& rows) const;
  // The first row of part `part` of `parts`, the rows being cut so that each part holds about as
  // many particles as the others (particles often fill a few rows: a sediment, a dilute layer).
  long first_row_of_part(long part, int parts) const;

  ExchangeRule rule_;
  int ny_;
  long rows_;
  std::vector<int> head_;        // per fluid cell: first particle attached there, -1 if none
  std::vector<int> next_;        // per particle: next particle at the same cell
  std::vector<long> row_of_;     // per particle: its fluid row, y + ny z
  std::vector<long> row_start_;  // per row: its first entry in by_row_ (and its first slot)
  std::vector<int> by_row_;      // the particles, row by row
  std::vector<long> cursor_;     // per part of the sort and row: a count, then where it places next
  std::vector<long> nodes_in_row_;  // per row: nodes listed
  // Per slot (row_start_[r] + k for the k-th node of row r): the node, its cell, what it reads
  // and what it gains.
  std::vector<Node> slot_node_;
  std::vector<long> slot_cell_;
  std::vector<fluid::DensityMomentum> slot_fluid_;
  std::vector<fluid::Vec3> slot_gained_;
};

template <class Rows>
void MomentumExchange::for_rows(parallel::ThreadPool* pool, int parts, const Rows& rows) const {
  if (pool && parts > 1) {
    pool->parallel_for(parts, parts, [&](long first_part, long end_part) {
      for (long r = first_row_of_part(first_part, parts); r < first_row_of_part(end_part, parts); ++r) rows(r);
    });
  } else {
    for (long r = 0; r < rows_; ++r) rows(r);
  }
}

template <class Fluid>
void MomentumExchange::compute(const std::vector<Node>& node, const std::vector<long>& cell,
                               const std::vector<double>& mass, const std::vector<fluid::Vec3>& momentum,
                               const Fluid& fluid, std::vector<fluid::Vec3>& particle_dp, parallel::ThreadPool* pool,
                               int parts) {
  particle_dp.resize(node.size());
  sort_by_row(node, pool, parts);
  for_rows(pool, parts, [&](long r) {
    group_row(r, node, cell);
    const long first = row_start_[r], count = nodes_in_row_[r];
    if (count == 0) return;
    fluid.gather_momenta(slot_node_.data() + first, count, slot_fluid_.data() + first);
    for (long slot = first; slot < first + count; ++slot)
      exchange_at(slot, slot_fluid_[slot], mass, momentum, particle_dp);
  });
}

template <class Fluid>
void MomentumExchange::inject(Fluid& fluid, parallel::ThreadPool* pool, int parts) const {
  for_rows(pool, parts, [&](long r) {
    if (nodes_in_row_[r] > 0)
      fluid.add_momenta(slot_node_.data() + row_start_[r], slot_gained_.data() + row_start_[r], nodes_in_row_[r]);
  });
}

}  // namespace lbsolid::coupling
