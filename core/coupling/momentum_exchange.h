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

// The nodes an exchange touched and the momentum each node's fluid gains, index for index: the
// list the fluid takes back in one batched call (FluidLattice::add_momenta).
struct ExchangedNodes {
  std::vector<Node> nodes;
  std::vector<fluid::Vec3> gained;
  long size() const { return static_cast<long>(nodes.size()); }
};

class MomentumExchange {
 public:
  // `row_length` fluid cells make a row (nx): the nodes are visited row after row.
  MomentumExchange(long cells, ExchangeRule rule, long row_length = 1)
      : rule_(rule), row_length_(row_length), head_(cells, -1) {}

  // `node[p]`, `cell[p]`, `mass[p]`, `momentum[p]` describe particle p; `fluid` answers
  // gather_momenta(nodes, count, out) with the pre-collision density and momentum of each node
  // (FluidLattice's batched call). Fills `particle_dp` (momentum each particle gives) and returns
  // the nodes whose fluid gains momentum, row by row (within a row in the order their first
  // particle comes), so that the fluid is read, and later written, a row at a time rather than
  // in the particles' order, which jumps between rows. The nodes are independent (each has its
  // own particles), so with a pool they are cut into `parts` ranges run on it, each reading its
  // nodes' fluid in one batch, with the same result bit for bit; `fluid` must then allow several
  // threads to gather at once (a const read).
  template <class Fluid>
  const ExchangedNodes& compute(const std::vector<Node>& node, const std::vector<long>& cell,
                                const std::vector<double>& mass, const std::vector<fluid::Vec3>& momentum,
                                const Fluid& fluid, std::vector<fluid::Vec3>& particle_dp,
                                parallel::ThreadPool* pool = nullptr, int parts = 1);

  ExchangeRule rule() const { return rule_; }
  std::size_t bytes_allocated() const {
    return head_.capacity() * sizeof(int) + next_.capacity() * sizeof(int) +
           touched_.capacity() * (2 * sizeof(long) + sizeof(int)) + row_start_.capacity() * sizeof(long) +
           result_.nodes.capacity() * sizeof(Node) + result_.gained.capacity() * sizeof(fluid::Vec3) +
           fluid_.capacity() * sizeof(fluid::DensityMomentum);
  }

 private:
  // Groups the particles by node (head_, next_) and lists the nodes row by row (first_, result_.nodes).
  void group_by_node(const std::vector<Node>& node, const std::vector<long>& cell);
  // The exchange at the i-th node listed, its fluid being `f`.
  void exchange_at(long i, const fluid::DensityMomentum& f, const std::vector<long>& cell,
                   const std::vector<double>& mass, const std::vector<fluid::Vec3>& momentum,
                   std::vector<fluid::Vec3>& particle_dp);

  ExchangeRule rule_;
  long row_length_;
  std::vector<int> head_;        // per fluid cell: first particle attached there, -1 if none
  std::vector<int> next_;        // per particle: next particle at the same cell
  std::vector<long> touched_;    // per node: its first particle, in particle order
  std::vector<long> row_of_;     // per node (as in touched_): its fluid row
  std::vector<long> row_start_;  // counting sort by row
  std::vector<long> first_;      // per node listed: its first particle
  std::vector<fluid::DensityMomentum> fluid_;  // per node listed: its fluid before the exchange
  ExchangedNodes result_;
};

template <class Fluid>
const ExchangedNodes& MomentumExchange::compute(const std::vector<Node>& node, const std::vector<long>& cell,
                                                const std::vector<double>& mass,
                                                const std::vector<fluid::Vec3>& momentum, const Fluid& fluid,
                                                std::vector<fluid::Vec3>& particle_dp, parallel::ThreadPool* pool,
                                                int parts) {
  particle_dp.resize(node.size());
  group_by_node(node, cell);
  const long count = result_.size();
  fluid_.resize(count);
  result_.gained.resize(count);
  auto range = [&](long begin, long end) {
    fluid.gather_momenta(result_.nodes.data() + begin, end - begin, fluid_.data() + begin);
    for (long i = begin; i < end; ++i) exchange_at(i, fluid_[i], cell, mass, momentum, particle_dp);
  };
  if (pool) {
    pool->parallel_for(count, parts, range);
  } else {
    range(0, count);
  }
  return result_;
}

}  // namespace lbsolid::coupling
