#pragma once
// The per-node momentum exchange (MODEL.md section 3). Every particle is attached to its nearest
// fluid node; at each node the fluid and all the particles there reach one common velocity
//   u* = (rho u_f + sum_p M_p u_p) / (rho + sum_p M_p),   dP_p = M_p (u_p - u*),
// which for a lone particle is exactly eq. 14, dP = Z (u_s - u_f) with 1/Z = 1/rho + 1/M.
// The fluid gains sum_p dP_p = sum_p M_p u_p - (sum_p M_p) u*, worked out per node from the
// sums, so that no pass over the particles is needed for it.
// The pairwise rule (eq. 14 applied to each particle against the same fluid state) is kept only
// to show why it is not used: with several particles on a node it over-corrects and can diverge.
//
// An exchange runs in three calls. locate() records each particle's cell. compute() cuts the
// cells into parts (ranges of about equal particle counts, from the last exchange's counts); each
// part walks its particles in index order (with several parts, sorted out by part beforehand),
// marks their cells in a bitmap, lists them in cell order (so that the fluid is read, and later
// written, in the order it is stored), walks the particles again summing them per node, reads its nodes' fluid in batches of
// kReadChunk nodes and works out each node's velocity u* and what its fluid gains. A node's
// particles are thus summed in index order whatever the number of parts: the result is the same
// bit for bit. particle_dp() then gives each particle its dP from its node's u* while the solid
// steps, and inject() gives the fluid its momentum after the fluid's step. No particle is sorted
// or moved.
//
// The listing is kept from one exchange to the next: a solid moves a small part of a spacing a
// step, so few particles change node. locate() notes those that did; compute() then moves each
// to its new node's slot (a node not listed yet gets a slot after the parts' own, out of cell
// order; a node left without particles keeps its slot, and its fluid gains exactly nothing) and
// sums every node again from slot_, skipping the marking, the listing and the slot lookups. Once
// more than 1/kRelistDivisor of the nodes' particles have moved since the last listing, the
// nodes are listed afresh. Each node's sums are still taken in particle index order, so the
// results are the same bit for bit whichever way the nodes were found.
//
// Where the fluid allows it (FluidLattice::can_exchange_in_step, and the common-velocity rule),
// the fluid is read and given its momentum inside its step instead (in_step_exchange.h):
// compute_sums() does all but the fluid's read, and step_fluid() steps the fluid with the
// exchange done at each node as the step stores it, in place of compute()'s read before the step
// and inject() after it. The two ways agree to round-off (the fluid read after the collision
// instead of before); each is the same bit for bit whatever the threads and the listing.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "coupling/node_locator.h"
#include "fluid/force_inline.h"
#include "fluid/in_step_exchange.h"
#include "fluid/node_exchange_types.h"
#include "parallel/thread_pool.h"
#include "solid/particle_vectors.h"

namespace lbsolid::coupling {

enum class ExchangeRule { kCommonVelocity, kPairwise };
const char* exchange_rule_name(ExchangeRule rule);

// The nodes an exchange touched and the momentum each node's fluid gains, index for index.
struct ExchangedNodes {
  std::vector<Node> nodes;
  std::vector<fluid::Vec3> gained;
  long size() const { return static_cast<long>(nodes.size()); }
};

// A fluid cell's index, x + nx (y + ny z); grids have fewer than 2^32 cells (FluidConfig).
using CellIndex = std::uint32_t;

class MomentumExchange final : private fluid::InStepExchange {
 public:
  // The cells are counted in at most this many blocks (plus one) to balance the parts: fine
  // enough to balance, few enough to sum every exchange.
  static constexpr long kBalanceBlocks = 4096;
  // The nodes are listed afresh once more than 1/kRelistDivisor of them have seen a particle move
  // since the last listing (each move leaves at most one slot empty and adds at most one out of
  // cell order). Measured on the bench's scenes, 8 and 16 did as well, 4 worse.
  static constexpr long kRelistDivisor = 16;

  // On a grid of nx x ny x nz fluid nodes.
  MomentumExchange(const std::array<int, 3>& grid, ExchangeRule rule);

  // Records cell_of(p), the cell of particle p's nearest node, for p in [0, n), in `parts`
  // ranges on `pool` (cell_of must allow that), noting the particles whose node changed.
  template <class CellOf>
  void locate(long n, const CellOf& cell_of, parallel::ThreadPool* pool = nullptr, int parts = 1);
  // The same, a range at a time: fill(first, end, cells) writes cells[p] for p in [first, end).
  template <class Fill>
  void locate_ranges(long n, const Fill& fill, parallel::ThreadPool* pool = nullptr, int parts = 1);
  // locate_ranges() for a caller that walks the particles itself, in ranges that cover [0, n)
  // (the solid's step, as it stores their positions): begin_locate(n), then a RangeLocator for
  // each range, on any thread, given the range's particles a block at a time in order.
  void begin_locate(long n);
  class RangeLocator;
  // The exchange of the located particles, `mass[p]` and `momentum[p]` describing particle p;
  // `fluid` answers gather_momenta(nodes, count, out) with the pre-collision density and momentum
  // of each node (FluidLattice's batched call; with a pool, from several threads at once).
  // `anchored` (per particle, or null for none): anchors hold their nodes still. A node with an
  // anchor has u* = 0 (infinite mass at rest): its fluid gains -(rho u_f), its other particles
  // give all their momentum, and the anchors there absorb the sum, shared equally (anchor_dp).
  template <class Fluid>
  void compute(const std::vector<double>& mass, const solid::ParticleVectors& momentum, const Fluid& fluid,
               parallel::ThreadPool* pool = nullptr, int parts = 1, const std::vector<char>* anchored = nullptr);
  // compute() but for the fluid's read: the nodes and their particles' sums, for step_fluid().
  void compute_sums(const std::vector<double>& mass, const solid::ParticleVectors& momentum,
                    parallel::ThreadPool* pool = nullptr, int parts = 1, const std::vector<char>* anchored = nullptr);
  // The fluid's step with the exchange of the last compute_sums() inside it: afterwards
  // particle_dp(), anchor_dp() and exchanged() give what compute() and inject() around a
  // step() would have, to round-off (exchanged() only where gains are kept: keep_gains()).
  // Needs fluid.can_exchange_in_step() and the common-velocity rule (std::logic_error otherwise).
  template <class Fluid>
  void step_fluid(Fluid& fluid);
  // The momentum particle p gives its node, given the mass and momentum compute() had for it;
  // D is the solid's dimension (a 2D exchange keeps no z: dp's z is the momentum's).
  template <int D>
  fluid::Vec3 particle_dp(long p, const fluid::Vec3& momentum, double mass) const {
    if (rule_ != ExchangeRule::kCommonVelocity) return pairwise_dp_[p];
    const double* u = compared_velocity().data() + D * static_cast<long>(slot_[p]);
    fluid::Vec3 dp{momentum[0] - mass * u[0], momentum[1] - mass * u[1], momentum[2]};
    if constexpr (D == 3) dp[2] -= mass * u[2];
    return dp;
  }
  // Asks the cache for what particle_dp(p) will read (its node's u*): the solid's step reads the
  // particles in index order, their nodes' slots lie in cell order.
  template <int D>
  void prefetch_particle_dp(long p) const {
    if (p < static_cast<long>(slot_.size())) __builtin_prefetch(compared_velocity().data() + D * static_cast<long>(slot_[p]));
  }
  // What anchored particle p gives its node (minus what it absorbs there): the node's fluid
  // momentum and the other particles' momenta, negated, over the node's anchors.
  fluid::Vec3 anchor_dp(long p) const { return slots_.vector(slots_.anchor_share, slot_[p]); }
  // Gives the fluid the momentum of the last compute() (fluid.add_momenta per part), in the same
  // parts: each node's slots are written by no other node. Call after the fluid's step.
  template <class Fluid>
  void inject(Fluid& fluid, parallel::ThreadPool* pool = nullptr) const;

  CellIndex cell(long p) const { return cell_[p]; }
  // The last compute()'s nodes (those with particles) and what their fluid gains, in cell order
  // (tests, diagnostics). After step_fluid() without anchors, only if keep_gains(true) came
  // before it (std::logic_error otherwise).
  ExchangedNodes exchanged() const;
  // Whether step_fluid() keeps each node's gain for exchanged(): at the cost of an array of
  // gains and one of velocities written and fetched again (off by default).
  void keep_gains(bool keep) { keep_gains_ = keep; }
  // Whether the last compute() listed its nodes afresh (tests, benchmarks).
  bool relisted() const { return relisted_; }
  ExchangeRule rule() const { return rule_; }
  std::size_t bytes_allocated() const;

 private:
  // Nodes whose fluid is read in one batch: 512 x 32 B stays in the L1 cache until it is used.
  static constexpr long kReadChunk = 512;
  // locate() compares a range's cells with the listed ones this many at a time, while they are
  // still in the L1 cache.
  static constexpr long kLocateChunk = 1024;
  static constexpr long kCompareGroup = 16;
  // exchange() asks for the slots this many on.
  static constexpr long kStepPrefetchAhead = 16;
  // keep_listing() asks for the marks of the move this many ahead.
  static constexpr std::size_t kPrefetchMoves = 8;
  // A cell's slot from its word of marks (slot_of_cell in the .cpp): 1/4 B a cell, read with one
  // line, where a slot a cell took 4 B and missed the cache in a dilute 3D box.
  using MarkWord = fluid::MarkWord;
  // fluid::InStepExchange: the slot of a node listed since the parts' own, and the exchange of a
  // run of slots (node_velocities).
  std::uint32_t other_slot(long cell) const override;
  void prefetch_other_slot(long cell) const override;
  void exchange(std::uint32_t first_slot, long count, const fluid::NodesFluid& fluid, fluid::NodesGain& gained) override;
  // Every listed node, slot by slot (part k's from base[k] on): the node, the total mass and
  // momentum of its particles, the velocity its particles are compared with (u*, or the fluid's u
  // for the pairwise rule), and what its fluid gains. The fluid read there is used as it is read,
  // not kept (but for its density under the pairwise rule). Vectors have `dimension` components
  // a slot (a 2D exchange moves a third less memory without the z's, which stay zero).
  struct Slots {
    int dimension = 3;
    std::vector<Node> node;
    std::vector<double> mass;
    std::vector<double> momentum;
    std::vector<double> pairwise_rho;  // the pairwise rule only
    std::vector<double> velocity;  // (in momentum instead when velocity_over_sums_)
    std::vector<double> gained;    // (not kept when velocity_over_sums_)
    std::vector<std::uint32_t> anchors;  // anchored particles at the node
    std::vector<double> anchor_share;    // what each of them gives the node (anchor_dp)
    long size() const { return static_cast<long>(node.size()); }
    void resize(std::size_t n);  // n records each, what they held dropped
    std::size_t bytes_allocated() const;
    // Slot s's vector in `of`, as a 3-vector.
    fluid::Vec3 vector(const std::vector<double>& of, long s) const {
      const double* v = of.data() + dimension * s;
      return {v[0], v[1], dimension == 3 ? v[2] : 0.0};
    }
  };
  struct Part {
    CellIndex first_cell = 0, end_cell = 0;  // a whole number of bitmap words, but at the grid's end
    long first_block = 0, end_block = 0;     // its counting blocks
    long base = 0, count = 0;                // its slots
    long first_particle = 0, end_particle = 0;  // its particles in order_ (when sorted_)
  };
  // Cuts [0, cells) into `parts` ranges at block boundaries, each with about as many particles of
  // the last exchange as the others; marks each part's cells and gives it its slots.
  void cut_parts(int parts, parallel::ThreadPool* pool);
  // With several parts: the particle indices grouped by part into order_ (each part's in index
  // order), so that a part walks its own particles only; sorted at each listing, and again only
  // when a moved particle changes part. Walking all particles in every part (filtering by cell)
  // made the exchange's own work grow with the parts: one thread running P parts after one
  // another, against one part, 1.36x at 8 parts and 1.83x at 16 for the 2D sheets at 1 per cell,
  // 1.60x and 2.4-2.9x for the 3D balls; sorted, 0.96x and 1.00x, 1.15x and 1.20x. With the
  // sort done every exchange, 2 parts on 2 threads lost (2D 1 per cell, exchange 9.0-11.2 ns a
  // particle walking all against 10.8-13.0 sorted); with the listing kept they gain (8.2-8.9
  // against 7.4-7.6).
  static_assert(kBalanceBlocks + 1 <= 65535, "a part's index must fit part_of_block_'s 16 bits");
  void sort_by_part(parallel::ThreadPool* pool);
  // visit(p) for the part's particles p, in index order. Always inlined: called inside
  // run_with_isa, it is then compiled for the CPU's instruction set with its caller (out of line
  // it was compiled for the baseline, and slot_of_cell's popcount became a library call).
  template <class Visit>
  LBSOLID_FORCE_INLINE void for_each_particle(const Part& part, const Visit& visit) const;
  // Marks the cells of the part's particles (and counts them by block for the next cut).
  void mark_cells(Part& part);
  // Lists the part's marked nodes in cell order, their sums zero. The marks stay until the next
  // listing clears them (clear_marks).
  void list_nodes(const Part& part);
  // Sums the mass and momentum of the part's particles per node, in index order: each particle's
  // slot found from the marks (and recorded in slot_) after a listing, or read from slot_.
  template <bool kSlotsFromMarks>
  void sum_particles(const Part& part, const std::vector<double>& mass, const solid::ParticleVectors& momentum,
                     const std::vector<char>* anchored);
  // An exchange's start: the listing kept (its moves applied) or made afresh, for `dimension`
  // components a vector.
  void begin_listing(int dimension, int parts, parallel::ThreadPool* pool, bool anchors);
  // The part's nodes listed (after a fresh listing) and their particles summed.
  void sum_part(const Part& part, const std::vector<double>& mass, const solid::ParticleVectors& momentum,
                const std::vector<char>* anchored);
  // Zeroes the sums of slots [first, first + count).
  void zero_sums(long first, long count);
  // Whether the last listing can be kept for an exchange in `parts` parts: the common-velocity
  // rule, its particles, parts and dimension unchanged and few enough moves (locate() noted them).
  // If so, gives the particles that changed node their new slots, `moves` of them.
  bool keep_listing(int parts, parallel::ThreadPool* pool, long& moves);
  // Lists the nodes afresh: clears the last listing's marks, cuts the parts and marks their cells.
  void relist(int parts, parallel::ThreadPool* pool);
  // The slot of cell c, a node not in the last listing, for a particle that moved there: the one
  // it was given after the parts' slots, or a new one.
  std::uint32_t extra_slot_of(CellIndex c);
  // Where cell c's entry of extra_table_ is, or the empty entry where it would go; its probe
  // starts at extra_table_home(c).
  std::size_t extra_table_entry(CellIndex c) const;
  std::size_t extra_table_home(CellIndex c) const {
    return static_cast<std::size_t>(((static_cast<std::uint64_t>(c) + 1) * 0x9E3779B97F4A7C15ULL) >> 32) &
           (extra_table_.size() - 1);
  }
  // The comparison velocity and gain of the slots [first, first + count), their fluid read in
  // batches.
  template <class Fluid>
  void read_and_compare(const Fluid& fluid, long first, long count);
  // The part's words of marks. A part starts on a word boundary, but for a part left empty at the
  // grid's end (its cells [cells_, cells_)): rounded up, it has no word, where rounded down it had
  // the last word of the part before it, and listed and cleared that part's marks as its own.
  static long first_word(const Part& part) { return (static_cast<long>(part.first_cell) + 63) >> 6; }
  static long end_word(const Part& part) { return (static_cast<long>(part.end_cell) + 63) >> 6; }
  // Unmarks the part's cells: the marks are all zero between exchanges.
  void clear_marks(const Part& part);
  // The comparison velocity and gain of the `count` nodes listed from slot `first` on, given
  // their fluid as read (`read[k]` for slot first + k); the gains into gained[dimension k ...].
  void node_velocities(long first, long count, const fluid::DensityMomentum* read, double* gained);
  // The same on the common-velocity rule without anchors: u* into velocity[D k ...].
  template <int D>
  void common_velocities(long first, long count, const fluid::DensityMomentum* read, double* velocity, double* gained);
  // common_velocities() inside the fluid's step without anchors (velocity_over_sums_), the
  // fluid and the gains axis by axis: each node's u* over its summed momentum (read just before)
  // and its mass set to zero once read (masses_cleared_). Always inlined: called inside
  // run_with_isa, so that it is compiled for the CPU's vectors.
  template <int D>
  LBSOLID_FORCE_INLINE void in_step_velocities(long first, long count, const fluid::NodesFluid& fluid,
                                               fluid::NodesGain& gained);
  // Where the last exchange put each slot's u* (particle_dp()).
  const std::vector<double>& compared_velocity() const { return velocity_over_sums_ ? slots_.momentum : slots_.velocity; }
  // The pairwise rule: each particle's dP (eq. 14) and its node's gain, their sum.
  void pairwise_gains(const Part& part, const std::vector<double>& mass, const solid::ParticleVectors& momentum);
  // work(k) for every part k, on the pool when there are several.
  template <class Work>
  void for_parts(parallel::ThreadPool* pool, const Work& work) const;
  // work(first, count) over the slots listed since the parts' own, in as many ranges as parts.
  template <class Work>
  void for_extra_slots(parallel::ThreadPool* pool, const Work& work) const;

  ExchangeRule rule_;
  std::array<int, 3> grid_;
  long cells_;
  int block_shift_;                      // cells of a counting block: 2^block_shift_, at least a word
  std::vector<CellIndex> cell_;          // per particle: its node's cell
  std::vector<std::uint32_t> slot_;      // per particle: its node's slot
  // The listing kept between exchanges. A range of locate()'s particles whose cells differ from
  // listed_cell_ (at most `particles` of them noted; `all` false when there were more).
  struct Moves {
    std::vector<std::uint32_t> particles;
    bool all = true;
    bool part_changed = false;  // (with sorted parts) one of them moved to another part's cells
  };
  std::vector<CellIndex> listed_cell_;   // per particle: the cell of its slot, as last listed or moved
  std::vector<Moves> moves_;             // from the last locate(), one a range, in no set order
  std::unique_ptr<std::mutex> moves_mutex_ = std::make_unique<std::mutex>();  // a range adding its moves
  // Set by begin_locate(): whether moves are noted (a listing could be kept), and how many at
  // most, beyond which the next exchange lists afresh anyway.
  bool locate_noting_ = false;
  long locate_allowed_ = 0;
  bool listed_ = false;                  // the marks and slots hold a listing
  bool relisted_ = false;                // the last compute() listed afresh
  bool part_changed_ = false;            // keep_listing(): some moved particle is another part's now
  int listed_dimension_ = 0;
  int listed_parts_ = 0;                 // the parts asked for (cut_parts may use fewer)
  long listed_slots_ = 0;                // the parts' slots, in cell order
  long extra_slots_ = 0;                 // slots of nodes listed since, after those
  long moves_since_listing_ = 0;
  // Their cells and slots, (cell + 1) << 32 | slot, by open addressing (linear probing, at most
  // half full: extra_slots_ <= listed_slots_ / kRelistDivisor); 0 is an empty entry.
  std::vector<std::uint64_t> extra_table_;
  std::vector<std::uint64_t> extra_marks_;  // per cell a bit: a node in extra_table_ is there
  std::vector<MarkWord> marks_;          // per cell a bit: a node of the last listing is there
  std::vector<long> block_count_;        // per block of cells: particles there at the last exchange
  std::vector<Part> parts_;
  bool sorted_ = false;                        // several parts, walking order_ (sort_by_part)
  std::vector<std::uint32_t> order_;           // particle indices, part by part
  std::vector<std::uint16_t> part_of_block_;   // the part of each counting block
  std::vector<long> range_counts_;             // particles per (range of indices, part), then offsets
  int parts_used_ = 0;
  bool anchors_present_ = false;  // the last compute() was given anchors
  // Inside the fluid's step, on the common-velocity rule without anchors and unless keep_gains_:
  // each node's u* is written over its summed momentum (read just before, by nothing after) and
  // its gain into the step's NodesGain, which the step adds at once. The step then fetches and writes
  // back no array of velocities or gains: 16 B a node each in 2D (docs/performance.md).
  bool velocity_over_sums_ = false;
  bool keep_gains_ = false;
  // On that path the exchange also sets each node's mass to zero as it reads it (its line is in
  // the cache then). A step_fluid() that completes so has visited every listed node
  // (step_exchanging exchanges each marked node once), so it leaves every slot's mass zero:
  // the next compute_sums() keeping the listing then sums without first zeroing the parts' slots
  // (24 B a node written, in 2D), a node's momentum starting afresh at its first particle
  // (sum_particles). Any other exchange in between clears the flag.
  bool masses_cleared_ = false;
  bool sums_start_cleared_ = false;  // this exchange's sums: masses_cleared_ at its start
  Slots slots_;
  std::vector<fluid::Vec3> pairwise_dp_;  // the pairwise rule: per particle
};

template <class Work>
void MomentumExchange::for_parts(parallel::ThreadPool* pool, const Work& work) const {
  if (pool && parts_used_ > 1) {
    pool->parallel_for(parts_used_, parts_used_, [&](long first, long end) {
      for (long k = first; k < end; ++k) work(static_cast<int>(k));
    });
  } else {
    for (int k = 0; k < parts_used_; ++k) work(k);
  }
}

template <class Work>
void MomentumExchange::for_extra_slots(parallel::ThreadPool* pool, const Work& work) const {
  if (extra_slots_ == 0) return;
  const auto run = [&](long first, long end) { work(listed_slots_ + first, end - first); };
  if (pool && parts_used_ > 1) pool->parallel_for(extra_slots_, parts_used_, run);
  else run(0, extra_slots_);
}

template <class Visit>
LBSOLID_FORCE_INLINE void MomentumExchange::for_each_particle(const Part& part, const Visit& visit) const {
  if (sorted_) {
    const std::uint32_t* __restrict order = order_.data();
    for (long i = part.first_particle; i < part.end_particle; ++i) visit(static_cast<long>(order[i]));
    return;
  }
  const long n = static_cast<long>(cell_.size());  // one part: all of them
  for (long p = 0; p < n; ++p) visit(p);
}

// One range's share of a locate (MomentumExchange::begin_locate).
class MomentumExchange::RangeLocator {
 public:
  explicit RangeLocator(MomentumExchange& exchange) : exchange_(&exchange) {}
  // The next block of the range, [first, end): fill(first, end, cells) writes cells[p] for p in
  // it; the particles whose cell differs from the listed one are noted.
  template <class Fill>
  void operator()(long first, long end, const Fill& fill);
  // Hands the range's moves to the exchange, after its last block.
  void finish() {
    std::lock_guard lock(*exchange_->moves_mutex_);
    exchange_->moves_.push_back(std::move(moves_));
  }

 private:
  MomentumExchange* exchange_;
  Moves moves_;
};

template <class Fill>
void MomentumExchange::RangeLocator::operator()(long first, long end, const Fill& fill) {
  CellIndex* __restrict cells = exchange_->cell_.data();
  const CellIndex* __restrict listed = exchange_->listed_cell_.data();
  fill(first, end, cells);
  if (!exchange_->locate_noting_ || !moves_.all) return;
  // Groups of kCompareGroup compared without a branch (vector instructions), and only a group
  // with a move looked into: about one in six at 1% of the particles moving a step.
  for (long group = first; group < end && moves_.all; group += kCompareGroup) {
    const long group_end = std::min(end, group + kCompareGroup);
    CellIndex differ = 0;
    for (long p = group; p < group_end; ++p) differ |= cells[p] ^ listed[p];
    if (differ == 0) continue;
    for (long p = group; p < group_end; ++p) {
      if (cells[p] == listed[p]) continue;
      if (static_cast<long>(moves_.particles.size()) == exchange_->locate_allowed_) {
        moves_.all = false;
        break;
      }
      moves_.particles.push_back(static_cast<std::uint32_t>(p));
    }
  }
}

template <class CellOf>
void MomentumExchange::locate(long n, const CellOf& cell_of, parallel::ThreadPool* pool, int parts) {
  locate_ranges(
      n,
      [&](long first, long end, CellIndex* cells) {
        for (long p = first; p < end; ++p) cells[p] = cell_of(p);
      },
      pool, parts);
}

template <class Fill>
void MomentumExchange::locate_ranges(long n, const Fill& fill, parallel::ThreadPool* pool, int parts) {
  begin_locate(n);
  const auto run = [&](long first, long end) {
    RangeLocator range(*this);
    for (long chunk = first; chunk < end; chunk += kLocateChunk) range(chunk, std::min(end, chunk + kLocateChunk), fill);
    range.finish();
  };
  if (pool && parts > 1) pool->parallel_for(n, parts, run);
  else run(0, n);
}

template <class Fluid>
void MomentumExchange::compute(const std::vector<double>& mass, const solid::ParticleVectors& momentum,
                               const Fluid& fluid, parallel::ThreadPool* pool, int parts,
                               const std::vector<char>* anchored) {
  begin_listing(momentum.dimension, pool ? parts : 1, pool, anchored != nullptr);
  for_parts(pool, [&](int k) {
    const Part& part = parts_[k];
    sum_part(part, mass, momentum, anchored);
    read_and_compare(fluid, part.base, part.count);
    if (rule_ == ExchangeRule::kPairwise) pairwise_gains(part, mass, momentum);
  });
  // The nodes listed since the parts' own, summed above by the parts their cells are in.
  for_extra_slots(pool, [&](long first, long count) { read_and_compare(fluid, first, count); });
}

template <class Fluid>
void MomentumExchange::step_fluid(Fluid& fluid) {
  if (rule_ != ExchangeRule::kCommonVelocity || !fluid.can_exchange_in_step())
    throw std::logic_error("MomentumExchange::step_fluid: this exchange cannot be done inside the fluid's step");
  if (parts_used_ > 0 && slots_.dimension != Fluid::D)
    throw std::logic_error("MomentumExchange::step_fluid: the solid's dimension is not the fluid's");
  marks = marks_.data();
  other_marks = extra_slots_ > 0 ? extra_marks_.data() : nullptr;
  velocity_over_sums_ = !anchors_present_ && !keep_gains_;
  fluid.step_exchanging(*this);
  masses_cleared_ = velocity_over_sums_;  // only once the step is complete (a throw leaves it false)
}

template <class Fluid>
void MomentumExchange::read_and_compare(const Fluid& fluid, long first, long count) {
  // The fluid read a chunk at a time into a buffer that stays in cache, and used at once.
  fluid::DensityMomentum read[kReadChunk];
  for (long chunk = first; chunk < first + count; chunk += kReadChunk) {
    const long chunk_count = std::min(kReadChunk, first + count - chunk);
    fluid.gather_momenta(slots_.node.data() + chunk, chunk_count, read);
    node_velocities(chunk, chunk_count, read, slots_.gained.data() + slots_.dimension * chunk);
  }
}

template <class Fluid>
void MomentumExchange::inject(Fluid& fluid, parallel::ThreadPool* pool) const {
  if (parts_used_ > 0 && slots_.dimension != Fluid::D)
    throw std::logic_error("MomentumExchange::inject: the solid's dimension is not the fluid's");
  for_parts(pool, [&](int k) {
    const Part& part = parts_[k];
    if (part.count > 0)
      fluid.add_momenta(slots_.node.data() + part.base, slots_.gained.data() + Fluid::D * part.base, part.count);
  });
  for_extra_slots(pool, [&](long first, long count) {
    fluid.add_momenta(slots_.node.data() + first, slots_.gained.data() + Fluid::D * first, count);
  });
}

}  // namespace lbsolid::coupling
