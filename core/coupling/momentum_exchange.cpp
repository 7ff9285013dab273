#include "coupling/momentum_exchange.h"

namespace lbsolid::coupling {

const char* exchange_rule_name(ExchangeRule rule) {
  switch (rule) {
    case ExchangeRule::kCommonVelocity: return "common-velocity";
    case ExchangeRule::kPairwise: return "pairwise";
  }
  return "?";
}

void MomentumExchange::group_by_node(const std::vector<Node>& node, const std::vector<long>& cell) {
  const int n = static_cast<int>(node.size());
  next_.resize(n);
  touched_.clear();
  for (int p = 0; p < n; ++p) {  // particles grouped by node in O(n)
    if (head_[cell[p]] < 0) touched_.push_back(p);
    next_[p] = head_[cell[p]];
    head_[cell[p]] = p;
  }
  // The nodes row by row: a counting sort on the row, stable.
  const long count = static_cast<long>(touched_.size());
  row_of_.resize(count);
  row_start_.assign(head_.size() / row_length_ + 2, 0);
  for (long i = 0; i < count; ++i) {
    row_of_[i] = cell[touched_[i]] / row_length_;
    ++row_start_[row_of_[i] + 1];
  }
  for (std::size_t r = 1; r < row_start_.size(); ++r) row_start_[r] += row_start_[r - 1];
  first_.resize(count);
  result_.nodes.resize(count);
  for (long i = 0; i < count; ++i) {
    const long at = row_start_[row_of_[i]]++;
    first_[at] = touched_[i];
    result_.nodes[at] = node[touched_[i]];
  }
}

void MomentumExchange::exchange_at(long i, const fluid::DensityMomentum& f, const std::vector<long>& cell,
                                   const std::vector<double>& mass, const std::vector<fluid::Vec3>& momentum,
                                   std::vector<fluid::Vec3>& particle_dp) {
  const long c = cell[first_[i]];
  fluid::Vec3 gained{0, 0, 0};
  if (rule_ == ExchangeRule::kCommonVelocity) {
    double total_mass = f.rho;
    fluid::Vec3 total_momentum = f.momentum;
    for (int p = head_[c]; p >= 0; p = next_[p]) {
      total_mass += mass[p];
      for (int a = 0; a < 3; ++a) total_momentum[a] += momentum[p][a];
    }
    const double inverse_mass = 1.0 / total_mass;
    const fluid::Vec3 common{total_momentum[0] * inverse_mass, total_momentum[1] * inverse_mass,
                             total_momentum[2] * inverse_mass};
    for (int p = head_[c]; p >= 0; p = next_[p])
      for (int a = 0; a < 3; ++a) {
        particle_dp[p][a] = momentum[p][a] - mass[p] * common[a];
        gained[a] += particle_dp[p][a];
      }
  } else {
    const fluid::Vec3 u{f.momentum[0] / f.rho, f.momentum[1] / f.rho, f.momentum[2] / f.rho};
    for (int p = head_[c]; p >= 0; p = next_[p]) {
      const double z = 1.0 / (1.0 / f.rho + 1.0 / mass[p]);
      for (int a = 0; a < 3; ++a) {
        particle_dp[p][a] = z * (momentum[p][a] / mass[p] - u[a]);
        gained[a] += particle_dp[p][a];
      }
    }
  }
  head_[c] = -1;  // ready for the next exchange
  result_.gained[i] = gained;
}

}  // namespace lbsolid::coupling
