#include "coupling/momentum_exchange.h"

#include <bit>

#include "fluid/force_inline.h"
#include "fluid/kernel_isa.h"

namespace lbsolid::coupling {

namespace {

// The set bits of `bits`: the popcnt instruction on the AVX2 and AVX-512 paths (and wherever the
// build targets a CPU that has it); elsewhere counted in registers, not by libgcc's call a word.
template <fluid::KernelIsa I>
LBSOLID_FORCE_INLINE long count_bits(std::uint64_t bits) {
#ifndef __POPCNT__
  if constexpr (I == fluid::KernelIsa::kBaseline) {
    bits -= (bits >> 1) & 0x5555555555555555ULL;
    bits = (bits & 0x3333333333333333ULL) + ((bits >> 2) & 0x3333333333333333ULL);
    bits = (bits + (bits >> 4)) & 0x0f0f0f0f0f0f0f0fULL;
    return static_cast<long>((bits * 0x0101010101010101ULL) >> 56);
  }
#endif
  return __builtin_popcountll(bits);
}

// The slot of marked cell c, of a word whose marks are `marks` and whose first marked cell has
// slot `first_slot`: that plus the marked cells before c.
template <fluid::KernelIsa I>
LBSOLID_FORCE_INLINE long slot_of_cell(std::uint64_t marks, std::uint32_t first_slot, CellIndex c) {
  return first_slot + count_bits<I>(marks & ((std::uint64_t{1} << (c & 63)) - 1));
}

}  // namespace

const char* exchange_rule_name(ExchangeRule rule) {
  switch (rule) {
    case ExchangeRule::kCommonVelocity: return "common-velocity";
    case ExchangeRule::kPairwise: return "pairwise";
  }
  return "?";
}

MomentumExchange::MomentumExchange(const std::array<int, 3>& grid, ExchangeRule rule)
    : rule_(rule),
      grid_(grid),
      cells_(static_cast<long>(grid[0]) * grid[1] * grid[2]),
      block_shift_(6),
      marks_(static_cast<std::size_t>((cells_ + 63) / 64)) {
  while ((cells_ >> block_shift_) > kBalanceBlocks) ++block_shift_;
  block_count_.assign(static_cast<std::size_t>((cells_ >> block_shift_) + 1), 0);
}

void MomentumExchange::Slots::resize(std::size_t n) {
  // Exactly n: a growing vector's resize would double its capacity (and the exchange's memory).
  // The old records are dropped first, not copied: a listing fills every record it uses afresh.
  const auto exactly = [](auto& v, std::size_t size) {
    v.clear();
    v.shrink_to_fit();
    v.reserve(size);
    v.resize(size);
  };
  exactly(node, n);
  exactly(mass, n);
  exactly(momentum, dimension * n);
  exactly(velocity, dimension * n);
  exactly(gained, dimension * n);
  exactly(anchors, n);
  exactly(anchor_share, dimension * n);
}

std::size_t MomentumExchange::Slots::bytes_allocated() const {
  return node.capacity() * sizeof(Node) + anchors.capacity() * sizeof(std::uint32_t) +
         (mass.capacity() + momentum.capacity() + velocity.capacity() + gained.capacity() + anchor_share.capacity() +
          pairwise_rho.capacity()) *
             sizeof(double);
}

std::size_t MomentumExchange::bytes_allocated() const {
  std::size_t moves = 0;
  for (const Moves& m : moves_) moves += sizeof(Moves) + m.particles.capacity() * sizeof(std::uint32_t);
  return (cell_.capacity() + slot_.capacity() + order_.capacity() + listed_cell_.capacity()) * sizeof(std::uint32_t) +
         moves + (extra_table_.capacity() + extra_marks_.capacity()) * sizeof(std::uint64_t) +
         marks_.capacity() * sizeof(MarkWord) + part_of_block_.capacity() * sizeof(std::uint16_t) +
         (block_count_.capacity() + range_counts_.capacity()) * sizeof(long) +
         parts_.capacity() * sizeof(Part) + slots_.bytes_allocated() + pairwise_dp_.capacity() * sizeof(fluid::Vec3);
}

void MomentumExchange::cut_parts(int parts, parallel::ThreadPool* pool) {
  const long blocks = static_cast<long>(block_count_.size());
  parts = static_cast<int>(std::clamp<long>(parts, 1, blocks));
  parts_.resize(parts);
  parts_used_ = parts;
  long total = 0;
  for (long count : block_count_) total += count;
  long block = 0, seen = 0;
  for (int k = 0; k < parts; ++k) {
    Part& part = parts_[k];
    part.first_block = block;
    part.first_cell = static_cast<CellIndex>(std::min(block << block_shift_, cells_));
    if (k == parts - 1) {
      block = blocks;
    } else if (total == 0) {  // nothing counted yet: equal shares of the cells
      block = blocks * (k + 1) / parts;
    } else {  // the first block at which the parts so far hold their share
      const long target = total * (k + 1) / parts;
      while (block < blocks && seen < target) seen += block_count_[block++];
    }
    part.end_cell = static_cast<CellIndex>(std::min(block << block_shift_, cells_));
    part.end_block = block;
  }
  sorted_ = parts > 1;
  if (sorted_) sort_by_part(pool);
  // Each part's nodes are its marked cells; its slots follow those of the parts before it.
  for_parts(pool, [&](int k) { mark_cells(parts_[k]); });
  long slots = 0;
  for (Part& part : parts_) {
    part.base = slots;
    slots += part.count;
  }
  // Room for the nodes a kept listing may add after these, one a move at most (keep_listing).
  const long room = slots + slots / kRelistDivisor + 1;
  if (slots_.size() < room || static_cast<long>(slots_.momentum.size()) < slots_.dimension * room) {
    // An eighth more, up to what a node a particle needs: the nodes' number creeps up from one
    // listing to the next, and growing each time by what it needed reallocated the records at
    // most listings (2D sheets at 1 a cell: 1.5 ns a particle a step, spread over the steps).
    const long particles = static_cast<long>(cell_.size());
    slots_.resize(std::max(room, std::min(room + room / 8, particles + particles / kRelistDivisor + 1)));
  }
  if (rule_ == ExchangeRule::kPairwise && static_cast<long>(slots_.pairwise_rho.size()) < slots)
    slots_.pairwise_rho.resize(slots);
}

void MomentumExchange::sort_by_part(parallel::ThreadPool* pool) {
  const int parts = parts_used_;
  part_of_block_.resize(block_count_.size());
  for (int k = 0; k < parts; ++k)
    std::fill(part_of_block_.begin() + parts_[k].first_block, part_of_block_.begin() + parts_[k].end_block,
              static_cast<std::uint16_t>(k));
  // Range r of the particle indices (one a thread of the pool) counts its particles per part; the
  // ranges then write their indices, in order, where their counts place them. Each range counts
  // and advances in a copy of its own: the ranges' rows of range_counts_ share cache lines, and
  // incremented there by two threads at once, every increment moved the line from one core to
  // the other (the sort of 105k particles on two threads took 0.86 ms, against 0.14 ms for the
  // whole listing on one).
  const long n = static_cast<long>(cell_.size());
  const int ranges = std::min(parts, pool->size());
  range_counts_.assign(static_cast<std::size_t>(ranges) * parts, 0);
  const auto each_range = [&](const auto& work) {
    pool->parallel_for(ranges, ranges, [&](long first, long end) {
      for (long r = first; r < end; ++r) work(r, n * r / ranges, n * (r + 1) / ranges);
    });
  };
  const CellIndex* __restrict cells = cell_.data();
  const std::uint16_t* __restrict part_of_block = part_of_block_.data();
  const int shift = block_shift_;
  each_range([&](long r, long first, long end) {
    std::vector<long> counts(parts, 0);
    for (long p = first; p < end; ++p) ++counts[part_of_block[cells[p] >> shift]];
    std::copy(counts.begin(), counts.end(), range_counts_.begin() + r * parts);
  });
  long at = 0;  // range_counts_ becomes where each (range, part) writes: part by part, range by range
  for (int k = 0; k < parts; ++k) {
    parts_[k].first_particle = at;
    for (int r = 0; r < ranges; ++r) {
      const long count = range_counts_[r * parts + k];
      range_counts_[r * parts + k] = at;
      at += count;
    }
    parts_[k].end_particle = at;
  }
  order_.resize(n);
  std::uint32_t* __restrict order = order_.data();
  each_range([&](long r, long first, long end) {
    std::vector<long> next(range_counts_.begin() + r * parts, range_counts_.begin() + (r + 1) * parts);
    for (long p = first; p < end; ++p) order[next[part_of_block[cells[p] >> shift]]++] = static_cast<std::uint32_t>(p);
  });
}

void MomentumExchange::mark_cells(Part& part) {
  const bool counts = parts_used_ > 1;  // for the next cut; one part needs no balance
  // Its own blocks: rounded from its cells, a part left empty at the grid's end had the last block
  // of the part before it, and zeroed its count while that part was counting.
  if (counts) std::fill(block_count_.begin() + part.first_block, block_count_.begin() + part.end_block, 0);
  const CellIndex* __restrict cells = cell_.data();
  MarkWord* __restrict marks = marks_.data();
  long* __restrict block_count = block_count_.data();
  long marked = 0;  // cells marked here for the first time: the part's nodes
  for_each_particle(part, [&](long p) LBSOLID_FORCE_INLINE_LAMBDA {
    const CellIndex c = cells[p];
    const std::uint64_t bit = std::uint64_t{1} << (c & 63);
    marked += (marks[c >> 6].cells & bit) == 0;
    marks[c >> 6].cells |= bit;
    if (counts) ++block_count[c >> block_shift_];
  });
  part.count = marked;
}

void MomentumExchange::begin_locate(long n) {
  cell_.resize(n);
  moves_.clear();
  // Moves are noted only where a listing could be kept, and not beyond what would make it relist.
  locate_noting_ = listed_ && static_cast<long>(listed_cell_.size()) == n;
  locate_allowed_ = std::max(0L, listed_slots_ / kRelistDivisor - moves_since_listing_);
}

void MomentumExchange::begin_listing(int dimension, int parts, parallel::ThreadPool* pool, bool anchors) {
  slots_.dimension = dimension;
  anchors_present_ = anchors;
  velocity_over_sums_ = false;
  // The anchor counts need their zeroing pass; the listed slots' masses and momenta do not, where
  // the last step's exchange left every mass zero (masses_cleared_: sum_particles starts afresh).
  sums_start_cleared_ = masses_cleared_ && !anchors;
  masses_cleared_ = false;
  long moves = 0;
  relisted_ = !keep_listing(parts, pool, moves);
  if (relisted_) {
    relist(parts, pool);
  } else {
    if (part_changed_) sort_by_part(pool);  // some particle moved to another part's cells
    zero_sums(listed_slots_, extra_slots_);
  }
  slot_.resize(cell_.size());
  if (rule_ == ExchangeRule::kPairwise) pairwise_dp_.resize(cell_.size());
}

void MomentumExchange::sum_part(const Part& part, const std::vector<double>& mass,
                                const solid::ParticleVectors& momentum, const std::vector<char>* anchored) {
  if (relisted_) {
    list_nodes(part);
    sum_particles<true>(part, mass, momentum, anchored);
  } else {
    if (!sums_start_cleared_) zero_sums(part.base, part.count);
    sum_particles<false>(part, mass, momentum, anchored);
  }
}

void MomentumExchange::compute_sums(const std::vector<double>& mass, const solid::ParticleVectors& momentum,
                                    parallel::ThreadPool* pool, int parts, const std::vector<char>* anchored) {
  begin_listing(momentum.dimension, pool ? parts : 1, pool, anchored != nullptr);
  for_parts(pool, [&](int k) { sum_part(parts_[k], mass, momentum, anchored); });
}

std::size_t MomentumExchange::extra_table_entry(CellIndex c) const {
  const std::uint64_t key = static_cast<std::uint64_t>(c) + 1;
  const std::size_t mask = extra_table_.size() - 1;
  std::size_t at = extra_table_home(c);
  while (extra_table_[at] != 0 && (extra_table_[at] >> 32) != key) at = (at + 1) & mask;
  return at;
}

void MomentumExchange::prefetch_other_slot(long cell) const {
  __builtin_prefetch(extra_table_.data() + extra_table_home(static_cast<CellIndex>(cell)));
}

std::uint32_t MomentumExchange::other_slot(long cell) const {
  const std::uint64_t entry = extra_table_[extra_table_entry(static_cast<CellIndex>(cell))];
  if (entry == 0) throw std::logic_error("MomentumExchange: a cell marked as another node's has no slot");
  return static_cast<std::uint32_t>(entry);
}

void MomentumExchange::exchange(std::uint32_t first_slot, long count, const fluid::NodesFluid& fluid,
                                fluid::NodesGain& gained) {
  // The step reaches the nodes in cell order, the order of their slots (but for the few listed
  // since): every line of the slots kStepPrefetchAhead on is asked for now (their lines are long
  // evicted by the step; asking for one line an array a call missed most of them in 3D).
  const long from = static_cast<long>(first_slot) + kStepPrefetchAhead;
  const long to = std::min(from + count, slots_.size());
  const int d = slots_.dimension;
  constexpr long kLine = 64 / sizeof(double);
  for (long at = from; at < to; at += kLine) __builtin_prefetch(slots_.mass.data() + at);
  const long first = d * static_cast<long>(first_slot);
  if (velocity_over_sums_) {
    for (long at = d * from; at < d * to; at += kLine) __builtin_prefetch(slots_.momentum.data() + at, 1);
    fluid::run_with_isa(fluid::kernel_isa(), [&]() LBSOLID_FORCE_INLINE_LAMBDA {
      if (d == 2) in_step_velocities<2>(first_slot, count, fluid, gained);
      else in_step_velocities<3>(first_slot, count, fluid, gained);
    });
    return;
  }
  for (long at = d * from; at < d * to; at += kLine) {
    __builtin_prefetch(slots_.momentum.data() + at);
    __builtin_prefetch(slots_.velocity.data() + at, 1);
  }
  // Anchors, or the gains kept (keep_gains): node by node as around the step, the gains then
  // handed over axis by axis.
  fluid::DensityMomentum read[fluid::kNodesAtOnce] = {};  // (count of them set)
  for (long k = 0; k < count; ++k) read[k] = fluid.node(k);
  const double* kept = slots_.gained.data() + first;
  node_velocities(first_slot, count, read, slots_.gained.data() + first);
  for (long k = 0; k < count; ++k)
    for (int a = 0; a < d; ++a) gained.momentum[a][k] = kept[d * k + a];
}

bool MomentumExchange::keep_listing(int parts, parallel::ThreadPool* pool, long& moves) {
  moves = 0;
  part_changed_ = false;
  const bool same = listed_ && rule_ == ExchangeRule::kCommonVelocity && parts == listed_parts_ &&
                    listed_dimension_ == slots_.dimension && listed_cell_.size() == cell_.size();
  if (!same) return false;
  for (const Moves& range : moves_) {
    if (!range.all) return false;
    moves += static_cast<long>(range.particles.size());
  }
  if (moves_since_listing_ + moves > listed_slots_ / kRelistDivisor) return false;
  // Moves to listed nodes, range by range on the pool (each particle's slot from the marks, which
  // no one writes now); those to nodes not listed yet are kept in `particles` for the table.
  const auto to_listed_nodes = [&](long first, long end) {
    for (long r = first; r < end; ++r) {
      std::vector<std::uint32_t>& particles = moves_[r].particles;
      std::size_t unlisted = 0;
      for (std::size_t i = 0; i < particles.size(); ++i) {
        // The marks of later moves asked for ahead: the moves' cells are far apart.
        if (i + kPrefetchMoves < particles.size()) __builtin_prefetch(&marks_[cell_[particles[i + kPrefetchMoves]] >> 6]);
        const std::uint32_t p = particles[i];
        const CellIndex c = cell_[p];
        if (sorted_ && part_of_block_[listed_cell_[p] >> block_shift_] != part_of_block_[c >> block_shift_])
          moves_[r].part_changed = true;
        listed_cell_[p] = c;
        const MarkWord& word = marks_[c >> 6];
        if ((word.cells >> (c & 63)) & 1)
          slot_[p] = static_cast<std::uint32_t>(slot_of_cell<fluid::kCompiledIsa>(word.cells, word.first_slot, c));
        else
          particles[unlisted++] = p;
      }
      particles.resize(unlisted);
    }
  };
  const long ranges = static_cast<long>(moves_.size());
  if (pool && ranges > 1) pool->parallel_for(ranges, static_cast<int>(ranges), to_listed_nodes);
  else to_listed_nodes(0, ranges);
  for (const Moves& range : moves_) {
    for (const std::uint32_t p : range.particles) slot_[p] = extra_slot_of(cell_[p]);
    part_changed_ = part_changed_ || range.part_changed;
  }
  moves_since_listing_ += moves;
  moves_.clear();  // applied: a second compute() without a locate() finds none
  return true;
}

std::uint32_t MomentumExchange::extra_slot_of(CellIndex c) {
  const std::size_t at = extra_table_entry(c);
  if (extra_table_[at] != 0) return static_cast<std::uint32_t>(extra_table_[at]);
  const long s = listed_slots_ + extra_slots_++;
  extra_table_[at] = (static_cast<std::uint64_t>(c) + 1) << 32 | static_cast<std::uint32_t>(s);
  if (extra_marks_.empty()) extra_marks_.assign(marks_.size(), 0);
  extra_marks_[c >> 6] |= std::uint64_t{1} << (c & 63);
  if (slots_.size() <= s || static_cast<long>(slots_.momentum.size()) < slots_.dimension * (s + 1))
    throw std::logic_error("MomentumExchange: more nodes added than the listing left room for");
  const long nx = grid_[0], ny = grid_[1];
  slots_.node[s] = {static_cast<int>(c % nx), static_cast<int>(c / nx % ny), static_cast<int>(c / nx / ny)};
  return static_cast<std::uint32_t>(s);
}

void MomentumExchange::relist(int parts, parallel::ThreadPool* pool) {
  if (listed_) for_parts(pool, [&](int k) { clear_marks(parts_[k]); });
  for (long s = listed_slots_; s < listed_slots_ + extra_slots_; ++s) {  // the extra nodes' marks
    const Node& node = slots_.node[s];
    const long c = node[0] + grid_[0] * (node[1] + static_cast<long>(grid_[1]) * node[2]);
    extra_marks_[c >> 6] &= ~(std::uint64_t{1} << (c & 63));
  }
  cut_parts(parts, pool);
  listed_slots_ = parts_.back().base + parts_.back().count;
  extra_slots_ = 0;
  extra_table_.assign(std::bit_ceil(static_cast<std::size_t>(2 * (listed_slots_ / kRelistDivisor + 1))), 0);
  moves_since_listing_ = 0;
  moves_.clear();
  listed_cell_ = cell_;
  listed_dimension_ = slots_.dimension;
  listed_parts_ = parts;
  listed_ = true;
}

void MomentumExchange::zero_sums(long first, long count) {
  const int d = slots_.dimension;
  std::fill_n(slots_.mass.data() + first, count, 0.0);
  std::fill_n(slots_.momentum.data() + d * first, d * count, 0.0);
  // The anchor counts are read only with anchors or by the pairwise rule (node_velocities).
  if (anchors_present_ || rule_ != ExchangeRule::kCommonVelocity) std::fill_n(slots_.anchors.data() + first, count, 0u);
}

void MomentumExchange::list_nodes(const Part& part) {
  // The marked cells in order, the node of each followed row by row from the part's first cell.
  const long nx = grid_[0], ny = grid_[1];
  long row = part.first_cell / nx, row_end = (row + 1) * nx;
  int y = static_cast<int>(row % ny), z = static_cast<int>(row / ny);
  long s = part.base;
  // Raw pointers: through the vectors every store would make the compiler reload their data.
  Node* __restrict node = slots_.node.data();
  MarkWord* __restrict marks = marks_.data();
  for (long w = first_word(part), end = end_word(part); w < end; ++w) {
    marks[w].first_slot = static_cast<std::uint32_t>(s);
    for (std::uint64_t bits = marks[w].cells; bits != 0; bits &= bits - 1) {
      const long c = 64 * w + __builtin_ctzll(bits);
      while (c >= row_end) {
        row_end += nx;
        if (++y == ny) {
          y = 0;
          ++z;
        }
      }
      node[s] = {static_cast<int>(c - (row_end - nx)), y, z};
      ++s;
    }
  }
  zero_sums(part.base, part.count);
}

template <bool kSlotsFromMarks>
void MomentumExchange::sum_particles(const Part& part, const std::vector<double>& mass,
                                     const solid::ParticleVectors& momentum, const std::vector<char>* anchored) {
  // Each node's particles summed in index order.
  double* __restrict slot_mass = slots_.mass.data();
  double* __restrict slot_momentum = slots_.momentum.data();
  std::uint32_t* __restrict slot_anchors = slots_.anchors.data();
  const MarkWord* __restrict marks = marks_.data();
  const CellIndex* __restrict cells = cell_.data();
  std::uint32_t* __restrict slot_of_particle = slot_.data();
  const double* __restrict masses = mass.data();
  const double* __restrict momenta = momentum.data;
  // D components per particle and per slot (a 2D solid stores no z).
  // Anchors count at their node and add neither mass nor momentum (theirs is infinite, at rest).
  const char* __restrict anchor = anchored ? anchored->data() : nullptr;
  // Counting a word's marks takes popcnt where the CPU has it: run_with_isa.
  auto sum = [&]<int D, bool kAnchors>(std::integral_constant<int, D>, std::bool_constant<kAnchors>) {
    fluid::run_with_isa(fluid::kernel_isa(), [&]<fluid::KernelIsa I>(fluid::IsaTag<I>) LBSOLID_FORCE_INLINE_LAMBDA {
      for_each_particle(part, [&](long p) LBSOLID_FORCE_INLINE_LAMBDA {
        long slot;
        if constexpr (kSlotsFromMarks) {
          const CellIndex c = cells[p];
          const MarkWord& word = marks[c >> 6];
          slot = slot_of_cell<I>(word.cells, word.first_slot, c);
          slot_of_particle[p] = static_cast<std::uint32_t>(slot);
        } else {
          slot = slot_of_particle[p];
        }
        if (kAnchors && anchor[p]) {
          ++slot_anchors[slot];
          return;
        }
        // A node whose mass is still zero has no particle summed yet: its momentum starts from
        // zero whatever the slot held (u*, after a step that cleared the masses), so that the sums
        // are those of a zeroed slot bit for bit (0 + x, as after zero_sums).
        const bool first_here = slot_mass[slot] == 0;
        slot_mass[slot] += masses[p];
        for (int a = 0; a < D; ++a)
          slot_momentum[slot * D + a] = (first_here ? 0.0 : slot_momentum[slot * D + a]) + momenta[p * D + a];
      });
    });
  };
  auto with_anchors = [&]<int D>(std::integral_constant<int, D> dimension) {
    if (anchor) sum(dimension, std::true_type{});
    else sum(dimension, std::false_type{});
  };
  if (momentum.dimension == 2) with_anchors(std::integral_constant<int, 2>{});
  else with_anchors(std::integral_constant<int, 3>{});
}

void MomentumExchange::clear_marks(const Part& part) {
  for (long w = first_word(part), end = end_word(part); w < end; ++w) marks_[w].cells = 0;
}

namespace {

// u* at a node and what its fluid gains there, from its fluid (density rho, momentum j) and its
// particles' sums (mass m, momentum sum[0, D)): the common-velocity rule. A node left without
// particles (its slot kept) has no momentum, whatever its slot holds: after a step that cleared
// the masses, the last step's u* (sum_particles starts a node afresh at its first particle).
// Elsewhere a zero mass comes with a zero sum, so this changes no value.
template <int D>
LBSOLID_FORCE_INLINE void common_velocity(double rho, const double (&j)[D], double m, const double* sum,
                                          double (&u)[D], double (&gain)[D]) {
  const double inverse_mass = 1.0 / (rho + m);
  // As bits, not a branch: the loop stays one of vectors (with a select GCC branched, node by node).
  const std::uint64_t keep = m == 0 ? 0 : ~std::uint64_t{0};
  for (int a = 0; a < D; ++a) {
    const double s = std::bit_cast<double>(std::bit_cast<std::uint64_t>(sum[a]) & keep);
    u[a] = (j[a] + s) * inverse_mass;
    gain[a] = s - m * u[a];
  }
}

}  // namespace

template <int D>
void MomentumExchange::common_velocities(long first, long count, const fluid::DensityMomentum* read,
                                          double* __restrict velocity, double* __restrict gained) {
  // The usual case (common-velocity rule, no anchors), without branches.
  const double* __restrict mass = slots_.mass.data() + first;
  const double* __restrict momentum = slots_.momentum.data() + D * first;
  for (long k = 0; k < count; ++k) {
    double j[D], u[D], gain[D];
    for (int a = 0; a < D; ++a) j[a] = read[k].momentum[a];
    common_velocity<D>(read[k].rho, j, mass[k], momentum + D * k, u, gain);
    for (int a = 0; a < D; ++a) {
      velocity[D * k + a] = u[a];
      gained[D * k + a] = gain[a];
    }
  }
}

template <int D>
LBSOLID_FORCE_INLINE void MomentumExchange::in_step_velocities(long first, long count, const fluid::NodesFluid& fluid,
                                                               fluid::NodesGain& gained) {
  double* __restrict mass = slots_.mass.data() + first;
  double* __restrict sums = slots_.momentum.data() + D * first;  // each node's u* goes over its sum
  for (long k = 0; k < count; ++k) {
    double j[D], u[D], gain[D];
    for (int a = 0; a < D; ++a) j[a] = fluid.momentum[a][k];
    common_velocity<D>(fluid.rho[k], j, mass[k], sums + D * k, u, gain);
    for (int a = 0; a < D; ++a) {
      sums[D * k + a] = u[a];
      gained.momentum[a][k] = gain[a];
    }
    mass[k] = 0;  // its line is in the cache: the next sums need no zeroing pass
  }
}

void MomentumExchange::node_velocities(long first, long count, const fluid::DensityMomentum* read,
                                        double* gained_from_first) {
  const int d = slots_.dimension;
  if (rule_ == ExchangeRule::kCommonVelocity && !anchors_present_) {
    double* velocity = slots_.velocity.data() + d * first;
    if (d == 2) common_velocities<2>(first, count, read, velocity, gained_from_first);
    else common_velocities<3>(first, count, read, velocity, gained_from_first);
    return;
  }
  for (long s = first; s < first + count; ++s) {
    const fluid::DensityMomentum& f = read[s - first];
    double* u = slots_.velocity.data() + d * s;
    double* gained = gained_from_first + d * (s - first);
    const double* momentum = slots_.momentum.data() + d * s;
    if (slots_.anchors[s] > 0) {  // held still: everything here comes to rest on the anchors
      const double share = 1.0 / slots_.anchors[s];
      for (int a = 0; a < d; ++a) {
        u[a] = 0;
        gained[a] = -f.momentum[a];
        slots_.anchor_share[d * s + a] = -(f.momentum[a] + momentum[a]) * share;
      }
    } else if (rule_ == ExchangeRule::kCommonVelocity) {
      const double inverse_mass = 1.0 / (f.rho + slots_.mass[s]);
      for (int a = 0; a < d; ++a) {
        u[a] = (f.momentum[a] + momentum[a]) * inverse_mass;
        gained[a] = momentum[a] - slots_.mass[s] * u[a];
      }
    } else {
      for (int a = 0; a < d; ++a) {
        u[a] = f.momentum[a] / f.rho;
        gained[a] = 0;
      }
      slots_.pairwise_rho[s] = f.rho;
    }
  }
}

void MomentumExchange::pairwise_gains(const Part& part, const std::vector<double>& mass,
                                      const solid::ParticleVectors& momentum) {
  // Eq. 14 per particle: its dP depends on its own mass, so the node's gain is their sum.
  for_each_particle(part, [&](long p) {
    const CellIndex c = cell_[p];
    const long s = slot_of_cell<fluid::kCompiledIsa>(marks_[c >> 6].cells, marks_[c >> 6].first_slot, c);
    const double z = 1.0 / (1.0 / slots_.pairwise_rho[s] + 1.0 / mass[p]);
    const fluid::Vec3 momentum_p = momentum[p];
    const fluid::Vec3 u = slots_.vector(slots_.velocity, s);
    for (int a = 0; a < 3; ++a) pairwise_dp_[p][a] = z * (momentum_p[a] / mass[p] - u[a]);
    for (int a = 0; a < slots_.dimension; ++a) slots_.gained[slots_.dimension * s + a] += pairwise_dp_[p][a];
  });
}

ExchangedNodes MomentumExchange::exchanged() const {
  if (velocity_over_sums_)
    throw std::logic_error("MomentumExchange::exchanged: the gains of an exchange inside the fluid's step are not kept "
                           "(keep_gains(true) before step_fluid() keeps them)");
  // The slots some particle is at (a kept listing may hold nodes left empty), in cell order (a
  // kept listing's later nodes follow the parts').
  std::vector<char> used(static_cast<std::size_t>(listed_slots_ + extra_slots_), 0);
  for (const std::uint32_t s : slot_) used[s] = 1;
  std::vector<std::pair<long, long>> cell_and_slot;
  for (long s = 0; s < static_cast<long>(used.size()); ++s) {
    const Node& n = slots_.node[s];
    if (used[s]) cell_and_slot.emplace_back(n[0] + grid_[0] * (n[1] + static_cast<long>(grid_[1]) * n[2]), s);
  }
  std::sort(cell_and_slot.begin(), cell_and_slot.end());
  ExchangedNodes out;
  for (const auto& [cell, s] : cell_and_slot) {
    out.nodes.push_back(slots_.node[s]);
    out.gained.push_back(slots_.vector(slots_.gained, s));
  }
  return out;
}

template void MomentumExchange::sum_particles<true>(const Part&, const std::vector<double>&, const solid::ParticleVectors&,
                                                    const std::vector<char>*);
template void MomentumExchange::sum_particles<false>(const Part&, const std::vector<double>&, const solid::ParticleVectors&,
                                                     const std::vector<char>*);

}  // namespace lbsolid::coupling
