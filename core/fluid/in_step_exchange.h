#pragma once
// A momentum exchange done inside the fluid's step (FluidLattice::step_exchanging). The coupling
// reads each node's fluid and gives it momentum; done apart, that is a read of the node's Q
// populations before the step and a write after it, two more passes over lines the step itself
// brings to the cache (the 3D suspension: 47-54 ns a node, docs/experiments/
// fused_exchange_probe.cpp). Inside the step, each node is exchanged as soon as the step has
// stored its post-collision populations, while they are still in the cache (29-30 ns a node): its
// density and momentum are read from them (a collision keeps the density and adds the force F
// to sum_i f_i c_i, so the momentum the step started from is sum_i f*_i c_i - F), and the gain
// is added to them as add_momenta adds it. Both ways give the same fluid to round-off.
#include <cstdint>

#include "fluid/force_inline.h"
#include "fluid/node_exchange_types.h"

namespace lbsolid::fluid {

// 64 cells' marks and the slot of the first marked one: the slot of a marked cell is that plus
// the marked cells before it in the word. 1/4 B a cell, read with one line.
struct MarkWord {
  std::uint64_t cells = 0;
  std::uint32_t first_slot = 0;
};

// What the coupling gives the step: its nodes and the exchange at each.
class InStepExchange {
 public:
  // Every node, one bit a cell (word c / 64), but those in `other_marks` (null when there are
  // none) whose slots other_slot() gives.
  const MarkWord* marks = nullptr;
  const std::uint64_t* other_marks = nullptr;
  virtual std::uint32_t other_slot(long cell) const = 0;
  // Asks for what other_slot(cell) will read, where that is memory the cache may not hold (the
  // step calls it for a word's other nodes before it exchanges the word's nodes).
  virtual void prefetch_other_slot(long /*cell*/) const {}
  // The exchange of nodes first_slot .. first_slot + count - 1 (count <= kNodesAtOnce) given
  // their fluid (node k of `fluid` for slot first_slot + k: density, and momentum
  // sum_i f_i c_i + F/2 as gather_momenta reads it before the step): writes the momentum their
  // fluid gains into `gained` (the step's own, in the cache; node k at [k]). Called from several
  // threads at once, for different slots.
  virtual void exchange(std::uint32_t first_slot, long count, const NodesFluid& fluid, NodesGain& gained) = 0;

 protected:
  ~InStepExchange() = default;
};

// What a kernel reports as it goes, when given one: finished(first, end) once cells [first, end)
// of one row have every post-collision population stored and none will be written again in the
// step. The marked ones among them are exchanged (node()); the scan of the marks is inline, and
// a row without nodes (row_nodes[row] == 0) ends it at one load: the kernels report a row in
// two or three pieces, and most of the 3D suspension's rows have no node (its coupled step 22-42
// ns a particle faster than when every report scanned its words: docs/performance.md).
class FinishedCells {
 public:
  FinishedCells(const MarkWord* marks, const std::uint64_t* other_marks, const std::uint32_t* row_nodes, long nx)
      : marks_(marks), other_marks_(other_marks), row_nodes_(row_nodes), nx_(nx) {}

  bool row_has_nodes(long row) const { return row_nodes_[row] != 0; }

  LBSOLID_FORCE_INLINE void operator()(long first, long end) {
    if (first >= end || row_nodes_[first / nx_] == 0) return;
    for (long w = first >> 6, last = (end - 1) >> 6; w <= last; ++w) {
      // The bits of [first, end) in word w.
      const int low = w == first >> 6 ? static_cast<int>(first & 63) : 0;
      std::uint64_t range = ~std::uint64_t{0} << low;
      if (w == last && ((end & 63) != 0)) range &= (std::uint64_t{1} << (end & 63)) - 1;
      const MarkWord word = marks_[w];
      const std::uint64_t hits = word.cells & range;
      const std::uint64_t others = other_marks_ ? other_marks_[w] & range : 0;
      if ((hits | others) == 0) continue;
      // The other nodes' slots are looked up in a table, a cache miss each: asked for first, so
      // that they arrive while the word's listed nodes are exchanged.
      for (std::uint64_t bits = others; bits != 0; bits &= bits - 1) prefetch_other_node(64 * w + __builtin_ctzll(bits));
      // The marked cells of the range have consecutive slots, from the marked cells before it on.
      if (hits != 0) {
        const std::uint64_t before = word.cells & ((std::uint64_t{1} << low) - 1);
        nodes(64 * w, hits, word.first_slot + static_cast<std::uint32_t>(__builtin_popcountll(before)));
      }
      for (std::uint64_t bits = others; bits != 0; bits &= bits - 1) other_node(64 * w + __builtin_ctzll(bits));
    }
  }

 protected:
  ~FinishedCells() = default;
  // The exchange at cells word_first + b for the set bits b of `bits` (cells of one row), of
  // nodes first_slot on, in that order.
  virtual void nodes(long word_first, std::uint64_t bits, std::uint32_t first_slot) = 0;
  // The exchange at `cell`, of the node InStepExchange::other_slot() gives.
  virtual void other_node(long cell) = 0;
  virtual void prefetch_other_node(long cell) = 0;

 private:
  const MarkWord* marks_;
  const std::uint64_t* other_marks_;
  const std::uint32_t* row_nodes_;  // by row
  long nx_;
};

}  // namespace lbsolid::fluid
