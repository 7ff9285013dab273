#pragma once
// The per-node momentum exchange (MODEL.md section 3). Every particle is attached to its nearest
// fluid node; at each node the fluid and all the particles there reach one common velocity
//   u* = (rho u_f + sum_p M_p u_p) / (rho + sum_p M_p),   dP_p = M_p (u_p - u*),
// which for a lone particle is exactly eq. 14, dP = Z (u_s - u_f) with 1/Z = 1/rho + 1/M.
// The pairwise rule (eq. 14 applied to each particle against the same fluid state) is kept only
// to show why it is not used: with several particles on a node it over-corrects and can diverge.
#include <vector>

#include "coupling/node_locator.h"
#include "parallel/thread_pool.h"

namespace lbsolid::coupling {

enum class ExchangeRule { kCommonVelocity, kPairwise };
const char* exchange_rule_name(ExchangeRule rule);

// One node's share of an exchange: the fluid gains `momentum`.
struct NodeExchange {
  Node node;
  fluid::Vec3 momentum;
};

class MomentumExchange {
 public:
  MomentumExchange(long cells, ExchangeRule rule) : rule_(rule), head_(cells, -1) {}

  // `node[p]`, `cell[p]`, `mass[p]`, `momentum[p]` describe particle p; `fluid_at(node)` returns
  // the pre-collision fluid Moments there. Fills `particle_dp` (momentum each particle gives) and
  // returns the nodes whose fluid gains momentum, in the order their first particle comes. The
  // nodes are independent (each has its own particles), so with a pool they are cut into `parts`
  // ranges run on it, with the same result bit for bit; fluid_at must then be safe to call from
  // several threads at once (a const read).
  template <class FluidMoments>
  const std::vector<NodeExchange>& compute(const std::vector<Node>& node, const std::vector<long>& cell,
                                           const std::vector<double>& mass,
                                           const std::vector<fluid::Vec3>& momentum,
                                           const FluidMoments& fluid_at,
                                           std::vector<fluid::Vec3>& particle_dp,
                                           parallel::ThreadPool* pool = nullptr, int parts = 1);

  ExchangeRule rule() const { return rule_; }
  std::size_t bytes_allocated() const {
    return head_.capacity() * sizeof(int) + next_.capacity() * sizeof(int) +
           nodes_.capacity() * (sizeof(NodeExchange) + sizeof(long));
  }

 private:
  ExchangeRule rule_;
  std::vector<int> head_;  // per fluid cell: first particle attached there, -1 if none
  std::vector<int> next_;  // per particle: next particle at the same cell
  std::vector<long> touched_;
  std::vector<NodeExchange> nodes_;
};

template <class FluidMoments>
const std::vector<NodeExchange>& MomentumExchange::compute(
    const std::vector<Node>& node, const std::vector<long>& cell, const std::vector<double>& mass,
    const std::vector<fluid::Vec3>& momentum, const FluidMoments& fluid_at,
    std::vector<fluid::Vec3>& particle_dp, parallel::ThreadPool* pool, int parts) {
  const int n = static_cast<int>(node.size());
  next_.resize(n);
  particle_dp.resize(n);
  touched_.clear();
  nodes_.clear();
  for (int p = 0; p < n; ++p) {  // particles grouped by node in O(n)
    if (head_[cell[p]] < 0) touched_.push_back(p);
    next_[p] = head_[cell[p]];
    head_[cell[p]] = p;
  }
  nodes_.resize(touched_.size());
  auto exchange_at = [&](long i) {
    const long first = touched_[i];
    const long c = cell[first];
    const auto m = fluid_at(node[first]);
    fluid::Vec3 gained{0, 0, 0};
    if (rule_ == ExchangeRule::kCommonVelocity) {
      double total_mass = m.rho;
      fluid::Vec3 total_momentum{m.rho * m.u[0], m.rho * m.u[1], m.rho * m.u[2]};
      for (int p = head_[c]; p >= 0; p = next_[p]) {
        total_mass += mass[p];
        for (int a = 0; a < 3; ++a) total_momentum[a] += momentum[p][a];
      }
      for (int p = head_[c]; p >= 0; p = next_[p])
        for (int a = 0; a < 3; ++a) {
          particle_dp[p][a] = momentum[p][a] - mass[p] * total_momentum[a] / total_mass;
          gained[a] += particle_dp[p][a];
        }
    } else {
      for (int p = head_[c]; p >= 0; p = next_[p]) {
        const double z = 1.0 / (1.0 / m.rho + 1.0 / mass[p]);
        for (int a = 0; a < 3; ++a) {
          particle_dp[p][a] = z * (momentum[p][a] / mass[p] - m.u[a]);
          gained[a] += particle_dp[p][a];
        }
      }
    }
    head_[c] = -1;
    nodes_[i] = {node[first], gained};
  };
  const long count = static_cast<long>(touched_.size());
  if (pool) {
    pool->parallel_for(count, parts, [&](long begin, long end) {
      for (long i = begin; i < end; ++i) exchange_at(i);
    });
  } else {
    for (long i = 0; i < count; ++i) exchange_at(i);
  }
  return nodes_;
}

}  // namespace lbsolid::coupling
