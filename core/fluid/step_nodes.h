#pragma once
// FluidLattice's StepNodes: the exchange at the nodes among the cells a part of a step reports
// finished (in_step_exchange.h). Included by fluid_lattice_methods.h, after FluidLattice.
#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>

#include "fluid/fluid_lattice.h"
#include "fluid/kernel_isa.h"
#include "lattice/lattice_traits.h"

namespace lbsolid::fluid {

// Each node's fluid is read from the populations just stored, and its gain added there. A run of
// neighbouring nodes inside a row (no edge cell: they share their slots) is read and given its
// gains across nodes, in blocks of kRunBlock in vector registers on the CPU's instruction set;
// node by node, scalar loads and sums were most of the exchange's cost inside the step in 2D.
// What is left of a run after its blocks goes node by node: blocks of any length (a count not
// known when compiled) gained less in 2D and lost in 3D, whose balls' rows are mostly shorter
// than a block (docs/performance.md). Each node gets the same operations in the same order as
// read() and add_at() give it alone (no contraction: -ffp-contract=off): the same values, bit for
// bit. In blocks (blocked_kernel.h) a node's populations are found through slot_index() and every
// node goes alone: the same values again, as the blocks' kernels give the arrays' bit for bit.
template <class L, class T>
class FluidLattice<L, T>::StepNodes final : public FinishedCells {
 public:
  // `local`: the step is a local (even) in-place step.
  StepNodes(const FluidLattice& fluid, InStepExchange& exchange, T* f, bool local)
      : FinishedCells(exchange.marks, exchange.other_marks, fluid.row_nodes_.data(), fluid.config_.nx),
        fluid_(fluid),
        exchange_(exchange),
        f_(f),
        local_(local),
        in_blocks_(fluid.blocks()) {}
  StepNodes(const StepNodes&) = delete;  // slots_ points into the object's own part_slots_
  StepNodes& operator=(const StepNodes&) = delete;

 private:
  static constexpr int kRunBlock = 8;

  void nodes(long word_first, std::uint64_t bits, std::uint32_t first_slot) override {
    long count = 0;
    run_with_isa(kernel_isa(), [&]() LBSOLID_FORCE_INLINE_LAMBDA {
      for_each_run(word_first, bits, [&](long cell, int n, bool interior) LBSOLID_FORCE_INLINE_LAMBDA {
        const int blocks = interior && !in_blocks_ ? n / kRunBlock : 0;
        for (int b = 0; b < blocks; ++b) read_block(cell + b * kRunBlock, count + b * kRunBlock);
        for (int k = blocks * kRunBlock; k < n; ++k) read_.set(count + k, read(cell + k));
        count += n;
      });
    });
    exchange_.exchange(first_slot, count, read_, gains_);
    count = 0;
    run_with_isa(kernel_isa(), [&]() LBSOLID_FORCE_INLINE_LAMBDA {
      for_each_run(word_first, bits, [&](long cell, int n, bool interior) LBSOLID_FORCE_INLINE_LAMBDA {
        const int blocks = interior && slots_->plain && !in_blocks_ ? n / kRunBlock : 0;
        for (int b = 0; b < blocks; ++b) add_block(cell + b * kRunBlock, count + b * kRunBlock);
        for (int k = blocks * kRunBlock; k < n; ++k) add(cell + k, gain_of(count + k));
        count += n;
      });
    });
  }
  void other_node(long cell) override {
    read_.set(0, read(cell));
    exchange_.exchange(exchange_.other_slot(cell), 1, read_, gains_);
    add(cell, gain_of(0));
  }
  // Node k's gain, as add() takes it.
  std::array<double, 3> gain_of(long k) const {
    return {gains_.momentum[0][k], gains_.momentum[1][k], D == 3 ? gains_.momentum[2][k] : 0.0};
  }
  void prefetch_other_node(long cell) override { exchange_.prefetch_other_slot(cell); }

  // visit(cell, n, interior) for the runs of cells word_first + b, b the set bits of `bits`
  // (cells of one row), in order: runs of neighbouring cells cut where a row's edge cell begins or
  // ends one; `interior` when the run's cells are the row's inner cells, whose slots and plan are
  // then set (locate()).
  template <class Visit>
  LBSOLID_FORCE_INLINE void for_each_run(long word_first, std::uint64_t bits, const Visit& visit) {
    const long nx = fluid_.config_.nx;
    while (bits != 0) {
      const int b = __builtin_ctzll(bits);
      const std::uint64_t from_b = bits >> b;
      const int length = ~from_b == 0 ? 64 - b : __builtin_ctzll(~from_b);
      bits = length + b >= 64 ? 0 : bits & (~std::uint64_t{0} << (b + length));
      long cell = word_first + b;
      const long end = cell + length;
      while (cell < end) {
        locate(cell);
        const long x = cell - row_first_;
        const long n = part_ == 1 ? std::min(end - cell, nx - 1 - x) : 1;  // inner cells: up to the last
        visit(cell, static_cast<int>(n), part_ == 1);
        cell += n;
      }
    }
  }

  // The row, plan and slots of `cell`'s part of its row. A row's nodes come together: its plan is
  // looked up (two divisions) once, and each part's slots worked out again only where its sources
  // differ from those that part last had (rows share their interior's, and most rows their edge
  // cells'). Kept per part: a body across the periodic x side has nodes at both ends of its rows,
  // which go part 0, 1, 2, 0, ... and with a single set of slots worked them out at nearly every
  // node there (152 offsets in blocks): 512 balls in 96^3 (bench_scenes.h), one thread, stepped
  // 27-43% slower with a column of balls across that side than without.
  LBSOLID_FORCE_INLINE void locate(long cell) {
    const long nx = fluid_.config_.nx;
    if (cell < row_first_ || cell >= row_first_ + nx) {
      row_ = cell / nx;
      row_first_ = row_ * nx;
      plan_ = &fluid_.plans_.for_row(row_);
      part_ = -1;
    }
    if (const int part = RowPlans<L, T>::part_of(static_cast<int>(cell - row_first_), static_cast<int>(nx)); part != part_) {
      part_ = part;
      const auto& sources = fluid_.plans_.sources(row_, part);
      if (&sources != part_sources_[part]) {
        part_slots_[part] = fluid_.injection_slots(sources, local_);
        part_sources_[part] = &sources;
      }
      slots_ = &part_slots_[part];
    }
  }

  // The node's fluid from its post-collision populations.
  DensityMomentum read(long cell) {
    locate(cell);
    std::array<T, Q> stored;
    if (in_blocks_)
      for (int i = 0; i < Q; ++i) stored[i] = f_[fluid_.template slot_index<true>(*slots_, i, cell)];
    else
      for (int i = 0; i < Q; ++i) stored[i] = f_[cell + slots_->offset[i]];
    DensityMomentum fluid = fluid_.density_momentum_of(stored, *plan_);
    // The collision added F to sum_i f_i c_i; density_momentum_of added F/2 more.
    if (fluid_.has_force_)
      for (int a = 0; a < 3; ++a) fluid.momentum[a] -= plan_->force[a];
    return fluid;
  }
  // read() for the kRunBlock inner nodes from `cell` on (slots_ and plan_ theirs), into read_'s
  // nodes [at, at + kRunBlock).
  LBSOLID_FORCE_INLINE void read_block(long cell, long at) {
    double drho[kRunBlock] = {}, j[3][kRunBlock] = {};
    // density_momentum_of()'s sums, direction by direction, across the nodes.
    [&]<int... I>(std::integer_sequence<int, I...>) LBSOLID_FORCE_INLINE_LAMBDA {
      ([&]() LBSOLID_FORCE_INLINE_LAMBDA {
        const T* __restrict from = f_ + cell + slots_->offset[I];
        for (int k = 0; k < kRunBlock; ++k) {
          const T g = from[k];
          const double v = static_cast<double>(g);
          drho[k] += g;
          j[0][k] = lattice::add_c<L, I, 0>(j[0][k], v);
          j[1][k] = lattice::add_c<L, I, 1>(j[1][k], v);
          j[2][k] = lattice::add_c<L, I, 2>(j[2][k], v);
        }
      }(), ...);
    }(std::make_integer_sequence<int, Q>{});
    const bool force = fluid_.has_force_;
    for (int k = 0; k < kRunBlock; ++k) read_.rho[at + k] = fluid_.config_.rho0 + drho[k];
    for (int a = 0; a < 3; ++a) {
      double* __restrict out = read_.momentum[a] + at;
      for (int k = 0; k < kRunBlock; ++k) {
        out[k] = j[a][k] + (force ? 0.5 * plan_->force[a] : 0.0);
        if (force) out[k] -= plan_->force[a];
      }
    }
  }

  // Its gain, through the slots read() last worked out: the cells of one row part.
  void add(long cell, const std::array<double, 3>& gain) {
    if (RowPlans<L, T>::part_of(static_cast<int>(cell - row_first_), fluid_.config_.nx) != part_) locate(cell);
    if (in_blocks_) fluid_.template add_at<true>(f_, *slots_, cell, gain.data());
    else fluid_.template add_at<false>(f_, *slots_, cell, gain.data());
  }
  // add() for the kRunBlock inner nodes from `cell` on (slots_ theirs, plain), the gains of
  // gains_'s nodes [at, at + kRunBlock).
  LBSOLID_FORCE_INLINE void add_block(long cell, long at) {
    const double* __restrict dp[3] = {gains_.momentum[0] + at, gains_.momentum[1] + at, gains_.momentum[2] + at};
    constexpr auto opp = lattice::opposite_table<L>();
    // add_at()'s terms, a pair of opposite directions at a time, across the nodes.
    [&]<int... I>(std::integer_sequence<int, I...>) LBSOLID_FORCE_INLINE_LAMBDA {
      ([&]() LBSOLID_FORCE_INLINE_LAMBDA {
        constexpr int J = opp[I];
        if constexpr (J > I) {
          double term[kRunBlock];
          for (int k = 0; k < kRunBlock; ++k) {
            double c_dot_dp = 0;
            c_dot_dp = lattice::add_c<L, I, 0>(c_dot_dp, dp[0][k]);
            c_dot_dp = lattice::add_c<L, I, 1>(c_dot_dp, dp[1][k]);
            if constexpr (D == 3) c_dot_dp = lattice::add_c<L, I, 2>(c_dot_dp, dp[2][k]);
            term[k] = L::w[I] * c_dot_dp / L::cs2;
          }
          T* __restrict to_i = f_ + cell + slots_->offset[I];
          for (int k = 0; k < kRunBlock; ++k) to_i[k] += static_cast<T>(term[k]);
          T* __restrict to_j = f_ + cell + slots_->offset[J];
          for (int k = 0; k < kRunBlock; ++k) to_j[k] += static_cast<T>(-term[k]);
        }
      }(), ...);
    }(std::make_integer_sequence<int, Q>{});
  }

  const FluidLattice& fluid_;
  InStepExchange& exchange_;
  T* f_;
  bool local_;
  bool in_blocks_;  // the populations are in blocks: no runs in vectors
  NodesFluid read_;  // a word's nodes' fluid
  NodesGain gains_;  // and their gains
  // The row of the last node and its first cell (none yet: no cell is within nx of it).
  long row_ = -1, row_first_ = -(1L << 62);
  const RowPlan<T, Q>* plan_ = nullptr;
  int part_ = -1;
  // Each part's slots and the sources they were worked out from (none yet), and the current part's.
  std::array<const PullSources<T, Q>*, 3> part_sources_{};
  std::array<InjectionSlots, 3> part_slots_{};
  const InjectionSlots* slots_ = &part_slots_[1];
};

}  // namespace lbsolid::fluid
