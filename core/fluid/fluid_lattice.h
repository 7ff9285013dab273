#pragma once
// A lattice-Boltzmann fluid on one lattice (D2Q9, D2Q7, D3Q19) in one precision (float, double):
// populations in arrays, or in blocks of cells where that is faster (population_storage.h,
// chosen_layout()), advanced by fused stream-collide kernels, either in place on one buffer
// (default) or between two buffers. Density and velocity are computed only on request.
//
// State convention: the fluid "at time t" is what the next step pulls (through the same boundary
// rules as the kernel), so every observer below gathers exactly what the kernel would see, and
// both streaming schemes give the same results (bit for bit with BGK; TRT and regularized agree to
// a few ulps, the compiler fusing their multiply-adds differently in vector and scalar code; and
// momentum injected into a population that then crosses a moving wall meets the wall's correction
// in the other order, which agrees to round-off: momentum_injection_test.cpp).
// initialize() sets that gathered state to the equilibrium of the given fields.
#include <array>
#include <cstdint>
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "fluid/fluid_config.h"
#include "fluid/in_step_exchange.h"
#include "fluid/node_exchange_types.h"
#include "fluid/population_storage.h"
#include "fluid/row_plan.h"
#include "parallel/thread_pool.h"

namespace lbsolid::fluid {

struct Moments {
  double rho;
  Vec3 u;  // physical velocity (sum f c + F/2) / rho
};

// Everything a FluidLattice changes as it runs, exactly as stored: restoring it into a lattice built
// from the same configuration continues the run bit for bit (checkpoints). Populations are kept as
// double whatever the precision (float -> double -> float is exact).
struct FluidRawState {
  long steps = 0;
  int current = 0;       // two-buffer: the buffer holding time t
  bool pulled = true;    // in place: the next step is an odd (pulling) step
  bool stepped = false;  // add_momentum() is allowed
  int buffers = 0;
  long cells = 0;
  std::vector<double> populations;  // [buffer][population][cell], shifted by w_i rho0 as stored
};

template <class L, class T>
class FluidLattice {
 public:
  using Lattice = L;
  using Real = T;
  static constexpr int Q = L::Q;
  static constexpr int D = L::D;

  // Throws std::invalid_argument naming every bad field (validate_fluid_config). Each step is cut
  // into config.threads parts, run by `pool` when one is given (shared with other lattices: a
  // daemon's sessions), else by a pool of config.threads threads of its own.
  explicit FluidLattice(const FluidConfig& config, std::shared_ptr<parallel::ThreadPool> pool = nullptr);
  ~FluidLattice();

  const FluidConfig& config() const { return config_; }
  long cells() const { return cells_; }
  long step_count() const { return steps_; }
  std::size_t bytes_allocated() const { return storage_.bytes() + row_nodes_.capacity() * sizeof(std::uint32_t); }
  PopulationLayout layout() const { return storage_.layout(); }
  // The layout `config` gets (config.layout, else blocks where the blocked kernels apply and the
  // CPU has AVX-512, where they were measured faster; else arrays). Throws std::invalid_argument
  // when config.layout asks for blocks where they do not apply.
  static PopulationLayout chosen_layout(const FluidConfig& config);

  // Equilibrium of the given density and velocity at every node.
  void initialize(const std::function<double(int, int, int)>& density,
                  const std::function<Vec3(int, int, int)>& velocity);
  void initialize_uniform(double density, const Vec3& velocity);

  void step();
  void run(long steps);
  // Whether step_exchanging() applies: in place, and every population stored as it is (no wall
  // rule with a scale or a correction: moving walls, inlets and outlets have them).
  bool can_exchange_in_step() const { return exchange_in_step_; }
  // step() with `exchange` done at its nodes inside it (in_step_exchange.h), in place of
  // gather_momenta before step() and add_momenta after it; the fluid and the nodes' readings then
  // agree with those to round-off. Throws std::logic_error where can_exchange_in_step() is false.
  void step_exchanging(InStepExchange& exchange);
  // MODEL.md eq. 12: adds w_i (c_i . dp) / c_s^2 to the post-collision populations that node
  // (x, y, z) produced in the step just taken, before they arrive downstream. The node's momentum
  // grows by exactly dp and its mass is unchanged. Call between step() and the next step().
  void add_momentum(int x, int y, int z, const Vec3& dp);
  // The coupling's two calls, batched: a fluid held elsewhere (a GPU, other processes) can answer
  // them for a whole list of nodes at once. Here the list is walked in order, the slots of a row's
  // nodes worked out once per row; nodes given row by row (x rising) read and write memory in
  // order. `out[k]` gets what moments(nodes[k]) describes; add_momenta is add_momentum for each
  // node with dp[D k .. D k + D - 1] (the nodes distinct; a 2D lattice's momenta have no z).
  void gather_momenta(const NodeIndex* nodes, long count, DensityMomentum* out) const;
  void add_momenta(const NodeIndex* nodes, const double* dp, long count);
  // The number of parts each step is cut into; a lattice with its own pool resizes it.
  void set_threads(int threads);

  FluidRawState raw_state() const;
  // Throws std::invalid_argument when the state was not taken from a lattice of this shape.
  void restore_raw_state(const FluidRawState& state);

  // Observers (computed on request).
  Moments moments(int x, int y, int z = 0) const;
  double density(int x, int y, int z = 0) const { return moments(x, y, z).rho; }
  Vec3 velocity(int x, int y, int z = 0) const { return moments(x, y, z).u; }
  // Adds u_x of each node of row (y, z) to `sum`, x ascending: the values velocity(x, y, z)[0]
  // gives, in the same order, with the row's plan looked up once (a velocity profile streamed
  // every few steps of a run then costs a fraction of a step instead of several).
  void add_row_velocity_x(int y, int z, double& sum) const;
  // Density and velocity of nodes first .. first + count - 1 of row (y, z): density[k] and
  // velocity[3k .. 3k + 2] are moments(first + k, y, z), bit for bit, with the row's sources looked
  // up once (a field read of a large grid then costs about one pass over the populations).
  void row_moments(int y, int z, int first, int count, double* density, double* velocity) const;
  std::array<double, L::Q> populations(int x, int y, int z = 0) const;  // f_i at time t
  double total_mass() const;
  Vec3 total_momentum() const;  // sum over nodes of sum_i f_i c_i
  // Position of node (x, y, z) in lattice units (D2Q7 rows are staggered and sqrt(3)/2 apart).
  static Vec3 position(int x, int y, int z = 0);

 private:
  bool in_place() const { return config_.streaming == StreamingScheme::kInPlace; }
  bool blocks() const { return storage_.layout() == PopulationLayout::kBlocks; }
  long cell(int x, int y, int z) const { return plans_.cell(x, y, z); }
  // Where population i of node (x, y, z) at time t is stored, and what to add to it.
  struct Slot {
    long index;
    T correction;
    T scale;  // the population is stored * scale + correction there
  };
  Slot slot(int i, int x, int y, int z) const;
  // Where population i of every node of one part of a row (RowPlans::part_of) is, as an offset
  // from the node's cell: at time t, to read (with a correction to add), and as the last step
  // wrote it after collision, to inject into.
  // A population is read as stored * scale + correction (a pressure outlet's scale is 0).
  // offset[i] = storage_.index(array[i], delta[i]) in arrays (a cell then adds its index); in
  // blocks a slot is worked out from array[i] and the cell + delta[i] (slot_index()).
  // In blocks, in_block[x][i] is where population i of a node at lane x (its cell mod W) lies
  // from its block's start (PopulationStorage::offset_in_blocks), tabulated once a row part:
  // index_in_blocks' division and remainder, twice a population a node, were most of the 3D
  // exchange's cost inside the step in blocks (docs/performance.md).
  using BlockOffsets = std::array<std::array<long, L::Q>, PopulationStorage<T>::kBlockCells>;
  struct RowSlots {
    std::array<int, L::Q> array;
    std::array<long, L::Q> delta;
    std::array<long, L::Q> offset;
    BlockOffsets in_block;  // in blocks only
    std::array<T, L::Q> correction;
    std::array<T, L::Q> scale;
    bool plain;  // every scale 1 and correction 0
  };
  RowSlots read_slots(const PullSources<T, L::Q>& sources) const;
  // A pressure outlet's rule with the velocity the flow brings to it: for each of its rows, the
  // velocity of the node one upstream (interior, so the outlet's own rule does not enter it). A
  // function of the state alone: set after every step, initialisation and restore.
  void refresh_outlet_corrections();
  // Where the last step left each post-collision population, and the scale it was stored with
  // (what is added there must be scaled alike).
  struct InjectionSlots {
    std::array<int, L::Q> array;
    std::array<long, L::Q> delta;
    std::array<long, L::Q> offset;
    BlockOffsets in_block;  // in blocks only
    std::array<T, L::Q> scale;
    bool plain;  // every scale 1
  };
  // `local`: the step that stored them was a local (even) in-place step.
  InjectionSlots injection_slots(const PullSources<T, L::Q>& sources, bool local) const;
  // add_momentum at cell c through slots of a known layout (dp: D values).
  template <bool kBlocks>
  LBSOLID_FORCE_INLINE void add_at(T* f, const InjectionSlots& slots, long c, const double* dp) const;
  // A part of a step's report of finished cells: the exchange at each of its nodes.
  class StepNodes;
  bool exchange_in_step_allowed() const;
  // The batched calls ask for a later node's populations while they work on this one: a lone
  // node's Q populations lie in Q arrays, Q cache misses that would otherwise be waited for one
  // node at a time (3D suspension, 1 thread: the exchange 105-117 -> 45-48 ns a particle). Not in
  // a batch of mostly consecutive cells (a dense 2D sheet): the hardware prefetcher streams
  // those, and asking again cost 1-2 ns a node. Skipping only the nodes just a run of cells
  // ahead lost all of the 3D gain: a ball's short rows do not start the hardware's streams.
  // 16 nodes on rather than 8 (in one process, alternating rounds, 3D suspension, three runs):
  // exchange 42.7-48.6 -> 40.1-46.4 ns a particle, injection 24.6-31.8 -> 21.8-27.5; 2D sheets
  // unchanged within noise; 4 was worse, 24 slowed the 2D injection.
  static constexpr long kPrefetchAhead = 16;
  bool worth_prefetching(const NodeIndex* nodes, long count) const {
    if (count <= kPrefetchAhead) return false;
    const NodeIndex& first = nodes[0];
    const NodeIndex& last = nodes[count - 1];
    return cell(last[0], last[1], last[2]) - cell(first[0], first[1], first[2]) > 2 * count;
  }
  // Where population i of the node at cell c is, for slots of a known layout.
  template <bool kBlocks, class Slots>
  long slot_index(const Slots& slots, int i, long c) const {
    if constexpr (kBlocks) {
      constexpr long W = PopulationStorage<T>::kBlockCells;
      const auto cell = static_cast<unsigned long>(c);  // never negative: unsigned, a shift and a mask
      return static_cast<long>(cell / W) * (L::Q * W) + slots.in_block[cell % W][i];
    } else {
      return c + slots.offset[i];
    }
  }
  // Slots' in_block, from their array and delta (in blocks).
  template <class Slots>
  void tabulate_in_block(Slots& slots) const {
    for (int lane = 0; lane < PopulationStorage<T>::kBlockCells; ++lane)
      for (int i = 0; i < Q; ++i) slots.in_block[lane][i] = storage_.offset_in_blocks(slots.array[i], slots.delta[i], lane);
  }
  // The later node's slots are taken to be this node's (exact within a row part, close
  // elsewhere: a prefetch needs no exact address). Always inlined, in every build: left as a
  // call, GCC 12 found the function free of side effects (it only prefetches) and deleted the
  // calls, which it did for the blocks' version (the division by W made it too large to inline
  // early) until this was seen in the disassembly: no prefetch in the blocked batched calls.
  template <bool kBlocks, class Slots>
  inline __attribute__((always_inline)) void prefetch_node(const T* f, const NodeIndex& node, const Slots& slots, bool for_write) const {
    // As an integer: a guessed slot may lie outside the arrays, where a pointer may not point.
    const std::uintptr_t base = reinterpret_cast<std::uintptr_t>(f);
    const long c = cell(node[0], node[1], node[2]);
    for (int i = 0; i < Q; ++i) {
      const auto* address = reinterpret_cast<const void*>(base + slot_index<kBlocks>(slots, i, c) * sizeof(T));
      if (for_write) __builtin_prefetch(address, 1);
      else __builtin_prefetch(address, 0);
    }
  }
  std::array<T, L::Q> gather(int x, int y, int z) const;  // shifted populations at time t
  std::array<T, L::Q> gather_at(const PullSources<T, L::Q>& sources, long cell) const;
  DensityMomentum density_momentum_of(const std::array<T, L::Q>& gathered, const RowPlan<T, L::Q>& plan) const;
  Moments moments_of(const std::array<T, L::Q>& gathered, const RowPlan<T, L::Q>& plan) const;
  // Where the interior nodes of row (y, z) find their populations at time t: population i of
  // node x is from[i][x] (+ correction[i] unless plain); in blocks, at
  // index_in_blocks(array[i], c0 + delta[i] + x) from f, c0 the row's first cell.
  struct InteriorRow {
    std::array<const T*, L::Q> from{};
    const T* f = nullptr;
    long c0 = 0;
    std::array<int, L::Q> array{};
    std::array<long, L::Q> delta{};
    std::array<T, L::Q> correction{};
    bool plain = false;
  };
  InteriorRow interior_row(int y, int z) const;
  static constexpr int kMomentBlock = 8;
  template <int A, class Visit>
  void for_each_interior_block(int y, int z, int first, int end, const Visit& visit) const;
  void check_in_place_slots() const;
  // initialize()'s work; with `uniform`, density and velocity are the same at every cell.
  template <class Density, class Velocity>
  void write_equilibrium(const Density& density, const Velocity& velocity, bool uniform);
  void check_in_place_slot(long cell) const;  // one cell's populations (throws if a rule breaks)
  // One step (with `exchange` inside it, when given).
  void step_with(InStepExchange* exchange);
  // work(first_row, end_row) for each of config_.threads parts of the rows, on the pool. With an
  // exchange inside the step, a part's rows hold about as many cells plus kNodeCells a node as
  // the others (the nodes can lie in a few rows: a 2D scene's sheets in its lowest tenth put all
  // the exchange's work on one thread of two), else as many rows.
  template <class Work>
  void for_row_parts(const InStepExchange* exchange, const Work& work);
  // row_nodes_ for the step's exchange: the nodes of each row, exact (a word of marks can span
  // rows).
  void count_row_nodes(const InStepExchange& exchange);
  // A node exchanged inside the step costs about this many cells' updates. 2D: 4, since the
  // node's cost fell to about 9 ns against 1.9 a cell (D2Q7 at 0.1 particle a cell, one thread);
  // with two threads, the step by step A/B of docs/performance.md gave 4 against 8 -2.9 and
  // -4.3 ns a particle, and 3 to 5 alike. 3D: 8, set when a node cost 25-40 ns against 6.5 a
  // cell and not measured again (the 3D suspension runs in blocks, split by planes).
  static constexpr long kNodeCells = L::D == 2 ? 4 : 8;
  // One step's fused kernels with the given collision policy (bgk_collision.h and siblings).
  template <class Collision>
  void launch(InStepExchange* exchange);
  // add_momenta and gather_momenta for a known layout.
  template <bool kBlocks>
  void add_momenta_in(const NodeIndex* nodes, const double* dp, long count);
  template <bool kBlocks>
  void gather_momenta_in(const NodeIndex* nodes, long count, DensityMomentum* out) const;
  // The step on populations in blocks (blocked_kernel.h), with `exchange` (null: none) at its nodes.
  template <bool kForce>
  void launch_blocks(InStepExchange* exchange);

  FluidConfig config_;
  long cells_;
  bool has_force_;
  RowPlans<L, T> plans_;
  PopulationStorage<T> storage_;
  bool exchange_in_step_;
  // The nodes of each row in the step's exchange (empty without one): the parts' balance, and a
  // report of a row without nodes ends at one load (3D suspensions leave most rows without).
  std::vector<std::uint32_t> row_nodes_;
  int current_ = 0;       // two-buffer: the buffer holding time t
  bool pulled_ = true;    // in-place: true when the next step is an odd (pulling) step
  long steps_ = 0;
  bool stepped_ = false;  // a step has run since the last initialize(): add_momentum is allowed
  bool owns_pool_;
  std::shared_ptr<parallel::ThreadPool> pool_;
};

}  // namespace lbsolid::fluid
