#include "coupling/momentum_exchange.h"

#include <algorithm>

namespace lbsolid::coupling {

const char* exchange_rule_name(ExchangeRule rule) {
  switch (rule) {
    case ExchangeRule::kCommonVelocity: return "common-velocity";
    case ExchangeRule::kPairwise: return "pairwise";
  }
  return "?";
}

MomentumExchange::MomentumExchange(const std::array<int, 3>& grid, ExchangeRule rule)
    : rule_(rule),
      ny_(grid[1]),
      rows_(static_cast<long>(grid[1]) * grid[2]),
      head_(static_cast<std::size_t>(grid[0]) * grid[1] * grid[2], -1) {}

std::size_t MomentumExchange::bytes_allocated() const {
  return head_.capacity() * sizeof(int) + (next_.capacity() + by_row_.capacity()) * sizeof(int) +
         (row_of_.capacity() + row_start_.capacity() + nodes_in_row_.capacity() + slot_cell_.capacity() +
          cursor_.capacity()) * sizeof(long) +
         slot_node_.capacity() * sizeof(Node) + slot_fluid_.capacity() * sizeof(fluid::DensityMomentum) +
         slot_gained_.capacity() * sizeof(fluid::Vec3);
}

void MomentumExchange::sort_by_row(const std::vector<Node>& node, parallel::ThreadPool* pool, int parts) {
  const long n = static_cast<long>(node.size());
  next_.resize(n);
  row_of_.resize(n);
  by_row_.resize(n);
  slot_node_.resize(n);  // a row has at most as many nodes as particles: its slots fit in its share
  slot_cell_.resize(n);
  slot_fluid_.resize(n);
  slot_gained_.resize(n);
  nodes_in_row_.assign(rows_, 0);
  row_start_.assign(rows_ + 1, 0);
  // At most 1 + n / rows parts, so that the per-part counters (parts x rows) stay within one per
  // row plus one per particle however many threads a session has and however short its rows.
  parts = pool ? static_cast<int>(std::clamp<long>(1 + n / std::max(rows_, 1L), 1, parts)) : 1;
  // Particles [n k / parts, n (k + 1) / parts) are part k's. Each part counts its particles per
  // row, then places them after those of the parts before it: the order of a serial sort.
  cursor_.assign(static_cast<std::size_t>(parts) * rows_, 0);
  auto for_parts = [&](const auto& work) {
    auto run = [&](long first, long end) {
      for (long k = first; k < end; ++k) work(&cursor_[k * rows_], n * k / parts, n * (k + 1) / parts);
    };
    if (parts == 1) run(0, 1);
    else pool->parallel_for(parts, parts, run);
  };
  for_parts([&](long* count, long first, long end) {
    for (long p = first; p < end; ++p) {
      row_of_[p] = node[p][1] + static_cast<long>(ny_) * node[p][2];
      ++count[row_of_[p]];
    }
  });
  for (long r = 0; r < rows_; ++r) {
    long placed = row_start_[r];
    for (long k = 0; k < parts; ++k) {
      const long count = cursor_[k * rows_ + r];
      cursor_[k * rows_ + r] = placed;
      placed += count;
    }
    row_start_[r + 1] = placed;
  }
  for_parts([&](long* cursor, long first, long end) {
    for (long p = first; p < end; ++p) by_row_[cursor[row_of_[p]]++] = static_cast<int>(p);
  });
}

long MomentumExchange::first_row_of_part(long part, int parts) const {
  if (part >= parts) return rows_;
  const long particles = row_start_[rows_];
  const long target = particles * part / parts;
  // The first row whose particles start at or after the target: row_start_ never decreases.
  return std::lower_bound(row_start_.begin(), row_start_.begin() + rows_, target) - row_start_.begin();
}

void MomentumExchange::group_row(long r, const std::vector<Node>& node, const std::vector<long>& cell) {
  const long first = row_start_[r];
  long count = 0;
  for (long k = first; k < row_start_[r + 1]; ++k) {
    const int p = by_row_[k];
    const long c = cell[p];
    if (head_[c] < 0) {
      slot_node_[first + count] = node[p];
      slot_cell_[first + count] = c;
      ++count;
    }
    next_[p] = head_[c];
    head_[c] = p;
  }
  nodes_in_row_[r] = count;
}

void MomentumExchange::exchange_at(long slot, const fluid::DensityMomentum& f, const std::vector<double>& mass,
                                   const std::vector<fluid::Vec3>& momentum, std::vector<fluid::Vec3>& particle_dp) {
  const long c = slot_cell_[slot];
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
  slot_gained_[slot] = gained;
}

ExchangedNodes MomentumExchange::exchanged() const {
  ExchangedNodes out;
  for (long r = 0; r < rows_; ++r)
    for (long slot = row_start_[r]; slot < row_start_[r] + nodes_in_row_[r]; ++slot) {
      out.nodes.push_back(slot_node_[slot]);
      out.gained.push_back(slot_gained_[slot]);
    }
  return out;
}

}  // namespace lbsolid::coupling
