#pragma once
// The definitions of FluidLattice's members, included only by the files that instantiate it, one
// per lattice (fluid_lattice_d2q9.cpp, _d2q7.cpp, _d3q19.cpp): the kernels are compiled once per
// instruction set with everything inlined, and one file holding all six instantiations was the
// slowest file of every build by far (3 minutes with gcc, 7 with clang's sanitizers, on 2 cores).
#include "fluid/fluid_lattice.h"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "fluid/bgk_collision.h"
#include "fluid/blocked_kernel.h"
#include "fluid/in_place_kernel.h"
#include "fluid/kernel_isa.h"
#include "fluid/regularized_collision.h"
#include "fluid/step_nodes.h"
#include "fluid/stream_collide_kernel.h"
#include "fluid/trt_collision.h"

namespace lbsolid::fluid {

namespace {

template <class L>
const FluidConfig& checked(const FluidConfig& config) {
  const auto errors = validate_fluid_config(config, L::D, L::hexagonal);
  if (!errors.empty()) {
    std::string message = std::string("invalid ") + L::name + " fluid: ";
    for (std::size_t k = 0; k < errors.size(); ++k) message += (k ? "; " : "") + errors[k];
    throw std::invalid_argument(message);
  }
  return config;
}

bool any_force(const FluidConfig& c) {
  auto nonzero = [](const Vec3& v) { return v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0; };
  bool force = nonzero(c.body_force);
  for (const auto& side : c.sides) force = force || (side.kind == WallKind::kFreeSlip && nonzero(side.traction));
  return force;
}

}  // namespace

template <class L, class T>
FluidLattice<L, T>::FluidLattice(const FluidConfig& config, std::shared_ptr<parallel::ThreadPool> pool)
    : config_(checked<L>(config)),
      cells_(static_cast<long>(config.nx) * config.ny * config.nz),
      has_force_(any_force(config)),
      plans_(config),
      storage_(config.streaming == StreamingScheme::kInPlace ? 1 : 2, Q, cells_, chosen_layout(config_)),
      exchange_in_step_(exchange_in_step_allowed()),
      owns_pool_(pool == nullptr),
      pool_(owns_pool_ ? std::make_shared<parallel::ThreadPool>(config_.threads) : std::move(pool)) {
  if (in_place()) check_in_place_slots();
  // Sized now, not at the first coupled step: the fluid's footprint (bytes_allocated, which a
  // session reports while a worker steps it) is fixed when it is built.
  if (exchange_in_step_) row_nodes_.assign(static_cast<std::size_t>(config_.ny) * config_.nz, 0);
  initialize_uniform(config_.rho0, {0, 0, 0});
}

// In place, the odd step writes population k of node y into the slot it read for opp(k), i.e.
// where f*_j' of node s' was stored, (j', s') being the source of opp(k) at y. That is right only
// if the rules are involutions: the source of opp(j') at s' must be k at y, with the same wall
// correction. Then every slot has one reader and the next step finds each population where it
// looks. Every rule here is such an involution; this check makes sure no corner breaks it.
template <class L, class T>
void FluidLattice<L, T>::check_in_place_slots() const {
  // A cell's sources depend on its row and its part of the row only (RowPlans::part_of: the first
  // cell, the interior, the last cell), and each lies at most one cell away in x. So the cells
  // x = 2 .. nx - 3 of a row, whose sources and their sources' sources lie in the row's interior
  // part, meet the same checks as x = 2: x = 0, 1, 2, nx - 3, nx - 2, nx - 1 of each row cover
  // every cell (checking every cell took as long as 130 steps on 192^3).
  static_assert([] {
    for (int k = 0; k < Q; ++k)
      if (L::c[k][0] < -1.0 || L::c[k][0] > 1.0) return false;
    return true;
  }());
  const int nx = config_.nx;
  const int xs[] = {0, 1, 2, nx - 3, nx - 2, nx - 1};
  for (long row = 0; row < cells_ / nx; ++row)
    for (int i = 0; i < 6; ++i)
      if (xs[i] >= 0 && xs[i] < nx && (i == 0 || xs[i] > xs[i - 1]))  // on a short row, each cell once
        check_in_place_slot(row * nx + xs[i]);
}

template <class L, class T>
void FluidLattice<L, T>::check_in_place_slot(long c) const {
  constexpr auto opp = lattice::opposite_table<L>();
  const int nx = config_.nx, ny = config_.ny;
  auto source = [&](int k, long c) -> const PullSource<T, Q>& {
    return plans_.sources(c / nx, RowPlans<L, T>::part_of(static_cast<int>(c % nx), nx))[k];
  };
  for (int k = 0; k < Q; ++k) {
    const auto& forward = source(opp[k], c);
    const long s = c + forward.delta;
    const auto& back = source(opp[forward.dir], s);
    if (back.dir != k || s + back.delta != c || back.correction != forward.correction ||
        back.scale != forward.scale) {
      const long row = c / nx;
      throw std::invalid_argument(
          "streaming: in-place streaming cannot express this combination of walls at node (" +
          std::to_string(c % nx) + ", " + std::to_string(row % ny) + ", " + std::to_string(row / ny) +
          "); choose two-buffer streaming");
    }
  }
}

template <class L, class T>
FluidLattice<L, T>::~FluidLattice() = default;

template <class L, class T>
PopulationLayout FluidLattice<L, T>::chosen_layout(const FluidConfig& config) {
  // Why the blocked kernels do not apply; empty when they do.
  std::string why;
  if (!BlockedKernels<L, T>::kLatticeFits) {
    why = std::string("the ") + L::name + " lattice (D3Q19 only)";
  } else if (config.streaming != StreamingScheme::kInPlace) {
    why = "two-buffer streaming (in place only)";
  } else if (config.collision != CollisionModel::kBgk) {
    why = std::string(collision_model_name(config.collision)) + " collisions (BGK only)";
  } else if (std::any_of(config.sides.begin(), config.sides.end(),
                         [](const SideBoundary& side) { return side.kind != WallKind::kPeriodic; })) {
    why = "a side that is not periodic (every side must be)";
  } else if (config.nx % BlockedKernels<L, T>::W != 0) {
    why = "nx = " + std::to_string(config.nx) + " (a multiple of " + std::to_string(BlockedKernels<L, T>::W) +
          " in this precision)";
  }
  if (config.layout) {
    if (*config.layout == PopulationLayout::kBlocks && !why.empty())
      throw std::invalid_argument("layout: blocks do not apply to " + why);
    return *config.layout;
  }
  // Measured faster with 512-bit vectors (a block's line is one vector). On the AVX2 path each
  // population takes two registers and the pulling step ran at 43 MLUPS against the arrays' 100
  // (128^3 double; 85 against 204-209 at 160^3 float): arrays there.
  return why.empty() && kernel_isa() == KernelIsa::kAvx512 ? PopulationLayout::kBlocks : PopulationLayout::kArrays;
}

template <class L, class T>
void FluidLattice<L, T>::set_threads(int threads) {
  if (threads < 1) throw std::invalid_argument("threads: must be at least 1, got " + std::to_string(threads));
  if (owns_pool_) pool_ = std::make_shared<parallel::ThreadPool>(threads);
  config_.threads = threads;
}

template <class L, class T>
FluidRawState FluidLattice<L, T>::raw_state() const {
  FluidRawState state;
  state.steps = steps_;
  state.current = current_;
  state.pulled = pulled_;
  state.stepped = stepped_;
  state.buffers = in_place() ? 1 : 2;
  state.cells = cells_;
  state.populations.reserve(static_cast<std::size_t>(state.buffers) * Q * cells_);
  // Population by population whatever the layout: a checkpoint restores into either.
  for (int b = 0; b < state.buffers; ++b)
    for (int i = 0; i < Q; ++i) {
      const T* f = storage_.buffer(b);
      if (!blocks()) {
        state.populations.insert(state.populations.end(), f + storage_.index_in_arrays(i, 0),
                                 f + storage_.index_in_arrays(i, cells_));
      } else {
        for (long c = 0; c < cells_; ++c) state.populations.push_back(f[storage_.index_in_blocks(i, c)]);
      }
    }
  return state;
}

template <class L, class T>
void FluidLattice<L, T>::restore_raw_state(const FluidRawState& state) {
  const int buffers = in_place() ? 1 : 2;
  if (state.buffers != buffers || state.cells != cells_ ||
      state.populations.size() != static_cast<std::size_t>(buffers) * Q * cells_)
    throw std::invalid_argument("fluid state: holds " + std::to_string(state.buffers) + " buffer(s) of " +
                                std::to_string(state.cells) + " cells (" +
                                std::to_string(state.populations.size()) + " values); this fluid has " +
                                std::to_string(buffers) + " of " + std::to_string(cells_) + " cells and " +
                                std::to_string(Q) + " populations");
  if (state.current < 0 || state.current >= buffers)
    throw std::invalid_argument("fluid state: current buffer " + std::to_string(state.current) + " out of range");
  std::size_t k = 0;
  for (int b = 0; b < buffers; ++b)
    for (int i = 0; i < Q; ++i) {
      T* f = storage_.buffer(b);
      for (long c = 0; c < cells_; ++c) f[storage_.index(i, c)] = static_cast<T>(state.populations[k++]);
    }
  steps_ = state.steps;
  current_ = state.current;
  pulled_ = state.pulled;
  stepped_ = state.stepped;
  refresh_outlet_corrections();
}

template <class L, class T>
void FluidLattice<L, T>::initialize(const std::function<double(int, int, int)>& density,
                                    const std::function<Vec3(int, int, int)>& velocity) {
  write_equilibrium(density, velocity, /*uniform=*/false);
}

template <class L, class T>
void FluidLattice<L, T>::initialize_uniform(double density, const Vec3& velocity) {
  write_equilibrium([density](int, int, int) { return density; }, [velocity](int, int, int) { return velocity; },
                    /*uniform=*/true);
}

template <class L, class T>
template <class Density, class Velocity>
void FluidLattice<L, T>::write_equilibrium(const Density& density, const Velocity& velocity, bool uniform) {
  using Collision = BgkCollision<L, T>;
  pulled_ = false;  // in place: the state is written as streamed populations
  stepped_ = false;
  T* f = storage_.buffer(in_place() ? 0 : current_);
  const T rho0 = static_cast<T>(config_.rho0);
  auto equilibrium_at = [&](int x, int y, int z, std::array<T, Q>& feq) {
    const T rho = static_cast<T>(density(x, y, z));
    const Vec3 v = velocity(x, y, z);
    const auto& force = plans_.for_row(y, z).force;
    // The populations carry sum f c = rho u - F/2, so the observed velocity is exactly v.
    T u[3];
    for (int a = 0; a < 3; ++a) u[a] = static_cast<T>(v[a]) - (has_force_ ? T(0.5) * force[a] / rho : T(0));
    const T usq = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    for (int i = 0; i < Q; ++i) feq[i] = Collision::equilibrium(i, rho, rho0, u, usq);
  };
  std::array<T, Q> feq;
  // First the local equilibrium everywhere (covers populations no node pulls). Uniform fields give
  // every cell of a row the same one (the force is a row's), written a population's row at a time
  // by the session's threads: this is where a new lattice's pages are first touched, most of the
  // time it takes to build (the fields of the general case are the caller's, called on its thread).
  const long rows = static_cast<long>(config_.ny) * config_.nz;
  if (uniform) {
    pool_->parallel_for(rows, config_.threads, [&](long begin, long end) {
      std::array<T, Q> row_feq;
      for (long row = begin; row < end; ++row) {
        equilibrium_at(0, static_cast<int>(row % config_.ny), static_cast<int>(row / config_.ny), row_feq);
        const long first = row * config_.nx, end = first + config_.nx;
        for (int i = 0; i < Q; ++i) {
          if (!blocks()) {
            std::fill_n(f + storage_.index_in_arrays(i, first), config_.nx, row_feq[i]);
          } else {
            constexpr int kW = PopulationStorage<T>::kBlockCells;
            for (long c = first; c < end; c += kW) std::fill_n(f + storage_.index_in_blocks(i, c), kW, row_feq[i]);
          }
        }
      }
    });
  } else {
    for (int z = 0; z < config_.nz; ++z)
      for (int y = 0; y < config_.ny; ++y)
        for (int x = 0; x < config_.nx; ++x) {
          equilibrium_at(x, y, z, feq);
          for (int i = 0; i < Q; ++i) f[storage_.index(i, cell(x, y, z))] = feq[i];
        }
  }
  // Then each population where the next step will look for it, so that gathering at time 0
  // returns the equilibrium. In place, the next step reads every population locally with no wall
  // rule (slot()): the first pass put them there already.
  if (!in_place()) {
    for (int z = 0; z < config_.nz; ++z) {
      for (int y = 0; y < config_.ny; ++y) {
        for (int x = 0; x < config_.nx; ++x) {
          equilibrium_at(x, y, z, feq);
          for (int i = 0; i < Q; ++i) {
            const Slot s = slot(i, x, y, z);
            // A rule that ignores what is stored (scale 0: the outlet's) is set by refresh below.
            f[s.index] = s.scale != T(0) ? (feq[i] - s.correction) * s.scale : feq[i];
          }
        }
      }
    }
  }
  refresh_outlet_corrections();
}

template <class L, class T>
bool FluidLattice<L, T>::exchange_in_step_allowed() const {
  if (!in_place()) return false;
  // Every population a step stores as it is: what the exchange reads there is f*_i itself.
  const auto plain = [](const PullSources<T, Q>& sources) {
    for (const auto& s : sources)
      if (s.scale != T(1) || s.correction != T(0)) return false;
    return true;
  };
  const long rows = static_cast<long>(config_.ny) * config_.nz;
  for (long row = 0; row < rows; ++row)
    for (int part = 0; part < 3; ++part)
      if (!plain(plans_.sources(row, part))) return false;
  return true;
}

template <class L, class T>
template <class Collision>
void FluidLattice<L, T>::launch(InStepExchange* exchange) {
  const typename Collision::Rates rates = Collision::rates(config_);
  const T rho0 = static_cast<T>(config_.rho0);
  const long rows = static_cast<long>(config_.ny) * config_.nz;
  const int nx = config_.nx;
  const long stride = storage_.stride();
  const auto& plans = plans_;
  // One kernel per (scheme, phase, force) combination; each of config_.threads row ranges goes
  // to one thread of the pool.
  if (exchange) count_row_nodes(*exchange);
  if constexpr (std::is_same_v<Collision, BgkCollision<L, T>> && BlockedKernels<L, T>::kLatticeFits) {
    if (blocks()) {  // chosen_layout() leaves blocks to BGK in place
      if (has_force_) launch_blocks<true>(exchange);
      else launch_blocks<false>(exchange);
      return;
    }
  }
  // Each part of the rows runs the kernel compiled for the CPU's instruction set (kernel_isa.h).
  const KernelIsa isa = kernel_isa();
  auto run_kernel = [&]<bool kForce>(std::bool_constant<kForce>) {
    if (!in_place()) {
      const T* src = storage_.buffer(current_);
      T* dst = storage_.buffer(current_ ^ 1);
      pool_->parallel_for(rows, config_.threads, [&](long begin, long end) {
        run_with_isa(isa, [&]() LBSOLID_FORCE_INLINE_LAMBDA {
          stream_collide_rows<L, T, Collision, kForce>(plans, src, dst, stride, nx, begin, end, rates, rho0);
        });
      });
    } else if (pulled_) {
      T* f = storage_.buffer(0);
      for_row_parts(exchange, [&](long begin, long end) {
        std::optional<StepNodes> nodes;  // each part its own: they keep the slots last worked out
        if (exchange) nodes.emplace(*this, *exchange, f, /*local=*/false);
        FinishedCells* finished = nodes ? &*nodes : nullptr;
        run_with_isa(isa, [&]<KernelIsa I>(IsaTag<I>) LBSOLID_FORCE_INLINE_LAMBDA {
          stream_collide_in_place_rows<L, T, Collision, kForce, shifted_pull_lanes<T>(I)>(plans, f, stride, nx, begin,
                                                                                         end, rates, rho0, finished);
        });
      });
    } else {
      T* f = storage_.buffer(0);
      for_row_parts(exchange, [&](long begin, long end) {
        std::optional<StepNodes> nodes;
        if (exchange) nodes.emplace(*this, *exchange, f, /*local=*/true);
        FinishedCells* finished = nodes ? &*nodes : nullptr;
        run_with_isa(isa, [&]() LBSOLID_FORCE_INLINE_LAMBDA {
          collide_local_rows<L, T, Collision, kForce>(plans, f, stride, nx, begin, end, rates, rho0, finished);
        });
      });
    }
  };
  if (has_force_) {
    run_kernel(std::true_type{});
  } else {
    run_kernel(std::false_type{});
  }
}

template <class L, class T>
void FluidLattice<L, T>::count_row_nodes(const InStepExchange& exchange) {
  const long nx = config_.nx;
  row_nodes_.assign(static_cast<std::size_t>(config_.ny) * config_.nz, 0);
  const long words = (cells_ + 63) / 64;
  for (long w = 0; w < words; ++w) {
    std::uint64_t bits = exchange.marks[w].cells | (exchange.other_marks ? exchange.other_marks[w] : 0);
    while (bits != 0) {  // the word's nodes row by row
      const long row = (64 * w + __builtin_ctzll(bits)) / nx;
      const long end = (row + 1) * nx - 64 * w;  // the row's end, as a bit of the word
      const std::uint64_t in_row = end >= 64 ? bits : bits & ((std::uint64_t{1} << end) - 1);
      row_nodes_[static_cast<std::size_t>(row)] += static_cast<std::uint32_t>(__builtin_popcountll(in_row));
      bits &= ~in_row;
    }
  }
}

template <class L, class T>
template <class Work>
void FluidLattice<L, T>::for_row_parts(const InStepExchange* exchange, const Work& work) {
  const long rows = static_cast<long>(config_.ny) * config_.nz;
  const int parts = config_.threads;
  if (!exchange || parts == 1) {
    pool_->parallel_for(rows, parts, work);
    return;
  }
  // The weight of rows [0, r) for each r: cells, plus kNodeCells a node (row_nodes_).
  const long nx = config_.nx;
  std::vector<long> before(static_cast<std::size_t>(rows) + 1, 0);
  long nodes = 0;
  for (long r = 0; r < rows; ++r) {
    nodes += row_nodes_[static_cast<std::size_t>(r)];
    before[r + 1] = (r + 1) * nx + kNodeCells * nodes;
  }
  std::vector<long> bounds(static_cast<std::size_t>(parts) + 1, rows);
  bounds[0] = 0;
  for (int k = 1; k < parts; ++k) {
    const long share = before[rows] / parts * k;
    bounds[k] = std::max(bounds[k - 1], static_cast<long>(std::lower_bound(before.begin(), before.end(), share) - before.begin()));
  }
  pool_->parallel_for(parts, parts, [&](long first, long end) {
    for (long k = first; k < end; ++k)
      if (bounds[k] < bounds[k + 1]) work(bounds[k], bounds[k + 1]);
  });
}

template <class L, class T>
template <bool kForce>
void FluidLattice<L, T>::launch_blocks(InStepExchange* exchange) {
  using Blocked = BlockedKernels<L, T>;
  const T omega = static_cast<T>(config_.omega), rho0 = static_cast<T>(config_.rho0);
  const long rows = static_cast<long>(config_.ny) * config_.nz;
  const typename Blocked::Grid grid{config_.nx, config_.ny, config_.nz};
  const long blocks_per_row = grid.blocks_per_row();
  const auto& plan_force = plans_.for_row(0).force;  // every side periodic: one force everywhere
  const T force[3] = {plan_force[0], plan_force[1], plan_force[2]};
  const KernelIsa isa = kernel_isa();
  T* f = storage_.buffer(0);
  const long nx = config_.nx;
  if (!pulled_) {
    pool_->parallel_for(rows, config_.threads, [&](long begin, long end) {
      std::optional<StepNodes> nodes;  // each part its own: they keep the slots last worked out
      if (exchange) nodes.emplace(*this, *exchange, f, /*local=*/true);
      run_with_isa(isa, [&]() LBSOLID_FORCE_INLINE_LAMBDA {
        // With an exchange, a row with nodes alone and reported at once, while its lines are in
        // the cache; the rows between such rows together.
        for (long row = begin, next; row < end; row = next) {
          next = end;
          if (nodes) {
            next = row + 1;
            if (!nodes->row_has_nodes(row))
              while (next < end && !nodes->row_has_nodes(next)) ++next;
          }
          Blocked::template local<kForce>(f, row * blocks_per_row, next * blocks_per_row, force, omega, rho0);
          if (nodes && next == row + 1) (*nodes)(row * nx, next * nx);
        }
      });
    });
    return;
  }
  // With an exchange, each part exchanges the nodes of its chunks as they finish: a node's slots
  // lie within a plane of its cell, and chunks that run at once are 5 planes apart (below).
  auto pull = [&](long first, long end) {
    std::optional<StepNodes> nodes;
    if (exchange) nodes.emplace(*this, *exchange, f, /*local=*/false);
    FinishedCells* finished = nodes ? &*nodes : nullptr;
    run_with_isa(isa, [&]() LBSOLID_FORCE_INLINE_LAMBDA {
      Blocked::template rows<kForce>(f, grid, first, end, force, omega, rho0, finished);
    });
  };
  // A chunk of rows reads and puts back a few lines beside it (blocked_kernel.h): the lines its
  // first cell's sources would be in for the row before the chunk, and its last cell's for the
  // row after. Their slots belong to cells of the plane before the chunk's first row or the one
  // after its last (the row before, shifted by a source offset and back by the reader's own,
  // wrapped), so chunks 3 planes apart touch no slot in common; 5 are kept apart here (one
  // plane each side more than needed, so that no slip in that reasoning can become a race).
  // The parts are ranges of planes. First every part does its planes but the 2 at each end,
  // all parts at once (two parts' planes so done are 5 or more apart, across the box's wrap
  // too); then the 4 planes around each boundary between parts, all boundaries at once where
  // every part has 9 planes or more (two boundaries' planes then lie 5 or more apart), else
  // one after another on this thread.
  const long nz = config_.nz, ny = config_.ny;
  const long parts = std::min<long>(config_.threads, nz);
  auto planes_of = [&](long k) { return std::pair<long, long>{nz * k / parts, nz * (k + 1) / parts}; };
  auto inner = [&](long k) {  // part k's planes but the 2 at each end
    const auto [begin, end] = planes_of(k);
    const long inner_begin = std::min(begin + 2, end);
    return std::pair<long, long>{inner_begin, std::max(end - 2, inner_begin)};
  };
  pool_->parallel_for(parts, static_cast<int>(parts), [&](long first, long end) {
    for (long k = first; k < end; ++k)
      if (const auto [begin, inner_end] = inner(k); begin < inner_end) pull(begin * ny, inner_end * ny);
  });
  // Boundary k: part k's planes after its inner ones and part k + 1's before them (wrapping).
  auto boundary = [&](long k) {
    pull(inner(k).second * ny, planes_of(k).second * ny);
    const long next = (k + 1) % parts;
    pull(planes_of(next).first * ny, inner(next).first * ny);
  };
  if (parts > 1 && nz / parts >= 9) {  // every part 9 planes or more
    pool_->parallel_for(parts, static_cast<int>(parts), [&](long first, long end) {
      for (long k = first; k < end; ++k) boundary(k);
    });
  } else {
    for (long k = 0; k < parts; ++k) boundary(k);
  }
}

template <class L, class T>
void FluidLattice<L, T>::step() {
  step_with(nullptr);
}

template <class L, class T>
void FluidLattice<L, T>::step_exchanging(InStepExchange& exchange) {
  if (!exchange_in_step_)
    throw std::logic_error("FluidLattice::step_exchanging: this fluid cannot exchange inside its step");
  step_with(&exchange);
}

template <class L, class T>
void FluidLattice<L, T>::step_with(InStepExchange* exchange) {
  // The collision is chosen here, once per step: each policy gets its own kernels, so BGK runs
  // exactly the code it ran before the other operators existed.
  switch (config_.collision) {
    case CollisionModel::kBgk: launch<BgkCollision<L, T>>(exchange); break;
    case CollisionModel::kTrt: launch<TrtCollision<L, T>>(exchange); break;
    case CollisionModel::kRegularized: launch<RegularizedCollision<L, T>>(exchange); break;
  }
  if (in_place()) {
    pulled_ = !pulled_;
  } else {
    current_ ^= 1;
  }
  ++steps_;
  stepped_ = true;
  refresh_outlet_corrections();
}

template <class L, class T>
void FluidLattice<L, T>::refresh_outlet_corrections() {
  const int nx = config_.nx;
  for (int side : {kXLow, kXHigh}) {
    const SideBoundary& outlet = config_.sides[side];
    if (outlet.kind != WallKind::kPressureOutlet) continue;
    const double rho_out = outlet.outflow_density > 0 ? outlet.outflow_density : config_.rho0;
    const int part = side == kXLow ? 0 : 2;
    const int upstream = side == kXLow ? std::min(1, nx - 1) : std::max(nx - 2, 0);
    for (int z = 0; z < config_.nz; ++z)
      for (int y = 0; y < config_.ny; ++y) {
        const long row = y + static_cast<long>(config_.ny) * z;
        const Vec3 u = moments(upstream, y, z).u;
        const double usq = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
        const auto& sources = plans_.sources(row, part);
        for (int i = 0; i < Q; ++i) {
          if (sources[i].scale != T(0)) continue;  // not set by the outlet (a wall's, or from inside)
          const double cu = L::c[i][0] * u[0] + L::c[i][1] * u[1] + L::c[i][2] * u[2];
          const double flow = cu / L::cs2 + cu * cu / (2 * L::cs2 * L::cs2) - usq / (2 * L::cs2);
          const T entering = static_cast<T>(L::w[i] * (rho_out * (1 + flow) - config_.rho0));
          plans_.set_edge_correction(row, part, i, entering);
          // In place before a local step, the node reads its own slots: the last pulling step
          // wrote the rule there as it stood then; it stands here now (two buffers read it now).
          if (in_place() && !pulled_) storage_.buffer(0)[storage_.index(i, cell(part == 0 ? 0 : nx - 1, y, z))] = entering;
        }
      }
  }
}

template <class L, class T>
void FluidLattice<L, T>::run(long steps) {
  for (long s = 0; s < steps; ++s) step();
}

template <class L, class T>
typename FluidLattice<L, T>::Slot FluidLattice<L, T>::slot(int i, int x, int y, int z) const {
  const long c = cell(x, y, z);
  if (in_place() && !pulled_) return {storage_.index(i, c), T(0), T(1)};
  const auto& s = plans_.sources(x, y, z)[i];
  // Two buffers keep f*_j at slot j of the source node; in place the even step left it reversed.
  const int stored_as = in_place() ? lattice::opposite<L>(s.dir) : s.dir;
  return {storage_.index(stored_as, c + s.delta), s.correction, s.scale};
}

template <class L, class T>
typename FluidLattice<L, T>::InjectionSlots FluidLattice<L, T>::injection_slots(const PullSources<T, L::Q>& sources,
                                                                                bool local) const {
  constexpr auto opp = lattice::opposite_table<L>();
  InjectionSlots slots;
  slots.delta.fill(0);
  slots.scale.fill(T(1));
  slots.plain = true;
  for (int i = 0; i < Q; ++i) {
    // Where the last step stored post-collision population i of the node: the buffer just
    // written holds it at i (two buffers); an even in-place step wrote it reversed, locally; an
    // odd one wrote it into the slot it had read population opp(i) from.
    if (!in_place()) {
      slots.array[i] = i;
    } else if (local) {
      slots.array[i] = opp[i];
    } else {
      const auto& s = sources[opp[i]];
      slots.array[i] = opp[s.dir];
      slots.delta[i] = s.delta;
      slots.scale[i] = s.scale;
      slots.plain = slots.plain && s.scale == T(1);
    }
    slots.offset[i] = storage_.index_in_arrays(slots.array[i], slots.delta[i]);
  }
  if (blocks()) tabulate_in_block(slots);
  return slots;
}

template <class L, class T>
void FluidLattice<L, T>::add_momentum(int x, int y, int z, const Vec3& dp) {
  const NodeIndex node{x, y, z};
  double components[D];
  for (int a = 0; a < D; ++a) components[a] = dp[a];  // a 2D lattice gives z nothing (c_z = 0)
  add_momenta(&node, components, 1);
}

template <class L, class T>
void FluidLattice<L, T>::add_momenta(const NodeIndex* nodes, const double* dp, long count) {
  if (!stepped_) throw std::logic_error("add_momentum: no step has produced post-collision populations yet");
  if (blocks()) add_momenta_in<true>(nodes, dp, count);
  else add_momenta_in<false>(nodes, dp, count);
}

template <class L, class T>
template <bool kBlocks>
void FluidLattice<L, T>::add_momenta_in(const NodeIndex* nodes, const double* dp, long count) {
  T* f = storage_.buffer(in_place() ? 0 : current_);
  const bool prefetch = worth_prefetching(nodes, count);
  long row_part = -1;  // of the slots below
  const PullSources<T, Q>* slots_from = nullptr;
  InjectionSlots slots{};
  for (long k = 0; k < count; ++k) {
    const auto& [x, y, z] = nodes[k];
    const int part = RowPlans<L, T>::part_of(x, config_.nx);
    if (const long row = y + static_cast<long>(config_.ny) * z; 3 * row + part != row_part) {
      // Rows share their interior's sources: the slots are worked out again only where they differ.
      if (const auto& sources = plans_.sources_of_part(y, z, part); &sources != slots_from) {
        slots = injection_slots(sources, /*local=*/pulled_);  // after a local step, pulled_ is set
        slots_from = &sources;
      }
      row_part = 3 * row + part;
    }
    if (prefetch && k + kPrefetchAhead < count) prefetch_node<kBlocks>(f, nodes[k + kPrefetchAhead], slots, /*for_write=*/true);
    add_at<kBlocks>(f, slots, cell(x, y, z), dp + D * k);
  }
}

template <class L, class T>
template <bool kBlocks>
void FluidLattice<L, T>::add_at(T* f, const InjectionSlots& slots, long c, const double* dp) const {
  // Direction by direction at compile time, a pair of opposite directions at a time: c_j = -c_i
  // and w_j = w_i, so j's term is exactly the negation of i's (rounding is symmetric), and the
  // division by c_s^2 (not a power of two on D3Q19) is paid once a pair. Zero velocity
  // components and the rest population (c = 0: it gains nothing) cost nothing (lattice::add_c).
  constexpr auto opp = lattice::opposite_table<L>();
  [&]<int... I>(std::integer_sequence<int, I...>) {
    ([&] {
      constexpr int J = opp[I];
      if constexpr (J > I) {
        static_assert(L::w[J] == L::w[I] && L::c[J][0] == -L::c[I][0] && L::c[J][1] == -L::c[I][1] &&
                      L::c[J][2] == -L::c[I][2]);
        double c_dot_dp = 0;
        c_dot_dp = lattice::add_c<L, I, 0>(c_dot_dp, dp[0]);
        c_dot_dp = lattice::add_c<L, I, 1>(c_dot_dp, dp[1]);
        if constexpr (D == 3) c_dot_dp = lattice::add_c<L, I, 2>(c_dot_dp, dp[2]);
        const double term = L::w[I] * c_dot_dp / L::cs2;
        T& to_i = f[slot_index<kBlocks>(slots, I, c)];
        T& to_j = f[slot_index<kBlocks>(slots, J, c)];
        if (slots.plain) {  // x * 1 is x
          to_i += static_cast<T>(term);
          to_j += static_cast<T>(-term);
        } else {
          to_i += static_cast<T>(term) * slots.scale[I];
          to_j += static_cast<T>(-term) * slots.scale[J];
        }
      }
    }(), ...);
  }(std::make_integer_sequence<int, Q>{});
}

template <class L, class T>
std::array<T, L::Q> FluidLattice<L, T>::gather(int x, int y, int z) const {
  // The row plan looked up once for all directions (the coupling calls this per particle per step).
  return gather_at(plans_.sources(x, y, z), cell(x, y, z));
}

template <class L, class T>
typename FluidLattice<L, T>::RowSlots FluidLattice<L, T>::read_slots(const PullSources<T, L::Q>& sources) const {
  // slot() for every direction.
  // Not value-initialised: gather_at() calls this for every cell it reads, and in_block (left
  // unset here: only the batched gather in blocks reads it, after tabulate_in_block()) is Q W words.
  RowSlots slots;
  slots.correction.fill(T(0));
  slots.scale.fill(T(1));
  slots.plain = true;
  constexpr auto opp = lattice::opposite_table<L>();
  for (int i = 0; i < Q; ++i) {
    if (in_place() && !pulled_) {
      slots.array[i] = i;
      slots.delta[i] = 0;
    } else {
      const auto& s = sources[i];
      slots.array[i] = in_place() ? opp[s.dir] : s.dir;
      slots.delta[i] = s.delta;
      slots.correction[i] = s.correction;
      slots.scale[i] = s.scale;
      slots.plain = slots.plain && s.correction == T(0) && s.scale == T(1);
    }
    slots.offset[i] = storage_.index_in_arrays(slots.array[i], slots.delta[i]);
  }
  return slots;
}

template <class L, class T>
std::array<T, L::Q> FluidLattice<L, T>::gather_at(const PullSources<T, L::Q>& sources, long c) const {
  const T* f = storage_.buffer(in_place() ? 0 : current_);
  const RowSlots slots = read_slots(sources);
  std::array<T, Q> g;
  for (int i = 0; i < Q; ++i)
    g[i] = f[storage_.index(slots.array[i], c + slots.delta[i])] * slots.scale[i] + slots.correction[i];
  return g;
}

template <class L, class T>
void FluidLattice<L, T>::gather_momenta(const NodeIndex* nodes, long count, DensityMomentum* out) const {
  if (blocks()) gather_momenta_in<true>(nodes, count, out);
  else gather_momenta_in<false>(nodes, count, out);
}

template <class L, class T>
template <bool kBlocks>
void FluidLattice<L, T>::gather_momenta_in(const NodeIndex* nodes, long count, DensityMomentum* out) const {
  const T* f = storage_.buffer(in_place() ? 0 : current_);
  const bool prefetch = worth_prefetching(nodes, count);
  long row_part = -1;  // of the plan and slots below
  const RowPlan<T, Q>* plan = nullptr;
  const PullSources<T, Q>* slots_from = nullptr;
  RowSlots slots{};
  for (long k = 0; k < count; ++k) {
    const auto& [x, y, z] = nodes[k];
    const int part = RowPlans<L, T>::part_of(x, config_.nx);
    if (const long row = y + static_cast<long>(config_.ny) * z; 3 * row + part != row_part) {
      plan = &plans_.for_row(y, z);
      // Rows share their interior's sources: the slots are worked out again only where they differ.
      if (const auto& sources = plans_.sources_of_part(y, z, part); &sources != slots_from) {
        slots = read_slots(sources);
        if constexpr (kBlocks) tabulate_in_block(slots);
        slots_from = &sources;
      }
      row_part = 3 * row + part;
    }
    if (prefetch && k + kPrefetchAhead < count) prefetch_node<kBlocks>(f, nodes[k + kPrefetchAhead], slots, /*for_write=*/false);
    const long c = cell(x, y, z);
    std::array<T, Q> g;
    // A plain part (no wall rule: scale 1, correction 0) reads the stored values as they are:
    // the sums below come out the same bit for bit (x * 1 + 0 only turns -0 into +0, and sums
    // that start from +0 never differ by the sign of a zero they add).
    if (slots.plain)
      for (int i = 0; i < Q; ++i) g[i] = f[slot_index<kBlocks>(slots, i, c)];
    else
      for (int i = 0; i < Q; ++i) g[i] = f[slot_index<kBlocks>(slots, i, c)] * slots.scale[i] + slots.correction[i];
    out[k] = density_momentum_of(g, *plan);
  }
}

template <class L, class T>
inline DensityMomentum FluidLattice<L, T>::density_momentum_of(const std::array<T, L::Q>& g,
                                                              const RowPlan<T, L::Q>& plan) const {
  double drho = 0, j[3] = {0, 0, 0};
  // Direction by direction at compile time, so that the zero velocity components cost nothing
  // (lattice::add_c); the row observers below sum in the same order with the same operations.
  [&]<int... I>(std::integer_sequence<int, I...>) {
    ([&] {
      const double v = static_cast<double>(g[I]);
      drho += g[I];
      j[0] = lattice::add_c<L, I, 0>(j[0], v);
      j[1] = lattice::add_c<L, I, 1>(j[1], v);
      j[2] = lattice::add_c<L, I, 2>(j[2], v);
    }(), ...);
  }(std::make_integer_sequence<int, Q>{});
  DensityMomentum m{config_.rho0 + drho, {0, 0, 0}};
  for (int a = 0; a < 3; ++a) m.momentum[a] = j[a] + (has_force_ ? 0.5 * plan.force[a] : 0.0);
  return m;
}

// Out of line: every caller of moments() runs this one compiled body. (Inlined, the compiler fused
// its multiply-adds differently in each caller, seen for u_y on D2Q7 with -march=native; since
// then -ffp-contract=off forbids that everywhere, which the row observers below rely on to give
// the same moments from their own loops.)
template <class L, class T>
[[gnu::noinline]] Moments FluidLattice<L, T>::moments_of(const std::array<T, L::Q>& g,
                                                         const RowPlan<T, L::Q>& plan) const {
  const DensityMomentum m = density_momentum_of(g, plan);
  return {m.rho, {m.momentum[0] / m.rho, m.momentum[1] / m.rho, m.momentum[2] / m.rho}};
}

template <class L, class T>
Moments FluidLattice<L, T>::moments(int x, int y, int z) const {
  const auto& plan = plans_.for_row(y, z);
  return moments_of(gather_at(plans_.sources(x, y, z), cell(x, y, z)), plan);
}

template <class L, class T>
typename FluidLattice<L, T>::InteriorRow FluidLattice<L, T>::interior_row(int y, int z) const {
  // The interior nodes share one set of sources: where each population lies, as an offset from
  // the node, and what to add to it (gather_at() for one node, here for the row).
  const auto& plan = plans_.for_row(y, z);
  const long c0 = cell(0, y, z);
  const T* f = storage_.buffer(in_place() ? 0 : current_);
  constexpr auto opp = lattice::opposite_table<L>();
  InteriorRow row;
  row.plain = in_place() && !pulled_;
  row.f = f;
  row.c0 = c0;
  for (int i = 0; i < Q; ++i) {
    const auto& source = plan.sources[1][i];
    row.array[i] = row.plain ? i : (in_place() ? opp[source.dir] : source.dir);
    row.delta[i] = row.plain ? 0 : source.delta;
    if (!blocks()) row.from[i] = f + storage_.index_in_arrays(row.array[i], c0 + row.delta[i]);
    if (!row.plain) row.correction[i] = source.correction;
  }
  return row;
}

// The interior nodes x in [first, end) of row (y, z) in blocks of kMomentBlock, population by
// population, so that the loads and sums run across nodes in vector registers: visit(x, n, drho,
// j) for each block of n nodes from x, with drho[k] and j[a][k] (a < A) the sums
// density_momentum_of() forms for node x + k, from its populations in the same order and with the
// same operations (no contraction: -ffp-contract=off), so every moment derived from them is the
// one moments() gives, bit for bit.
template <class L, class T>
template <int A, class Visit>
void FluidLattice<L, T>::for_each_interior_block(int y, int z, int first, int end, const Visit& visit) const {
  const InteriorRow row = interior_row(y, z);
  const auto sums = [&](int x, int n, const auto& population) {
    double drho[kMomentBlock] = {}, j[A][kMomentBlock] = {};
    [&]<int... I>(std::integer_sequence<int, I...>) {
      ([&] {
        for (int k = 0; k < n; ++k) {
          const T g = population(I, x + k);
          const double v = static_cast<double>(g);
          drho[k] += g;
          if constexpr (A > 0) j[0][k] = lattice::add_c<L, I, 0>(j[0][k], v);
          if constexpr (A > 1) j[1][k] = lattice::add_c<L, I, 1>(j[1][k], v);
          if constexpr (A > 2) j[2][k] = lattice::add_c<L, I, 2>(j[2][k], v);
        }
      }(), ...);
    }(std::make_integer_sequence<int, Q>{});
    visit(x, n, drho, j);
  };
  const auto sweep = [&](const auto& stored) {
    const auto corrected = [&](int i, int x) { return stored(i, x) + row.correction[i]; };
    for (int x = first; x < end; x += kMomentBlock) {
      const int n = std::min(kMomentBlock, end - x);
      if (n == kMomentBlock) {  // a constant count: the block's loops unroll
        if (row.plain) sums(x, kMomentBlock, stored);
        else sums(x, kMomentBlock, corrected);
      } else if (row.plain) {
        sums(x, n, stored);
      } else {
        sums(x, n, corrected);
      }
    }
  };
  if (blocks())
    sweep([&](int i, int x) { return row.f[storage_.index_in_blocks(row.array[i], row.c0 + row.delta[i] + x)]; });
  else
    sweep([&](int i, int x) { return row.from[i][x]; });
}

// A profile of a 192 x 96 D2Q9 session took about two steps node by node (out-of-line
// moments_of(), three divisions); under the 64-client load, profiles took 11% of all CPU.
template <class L, class T>
void FluidLattice<L, T>::add_row_velocity_x(int y, int z, double& sum) const {
  const int nx = config_.nx;
  const auto edge = [&](int x) { sum += moments(x, y, z).u[0]; };
  if (nx <= 2) {
    for (int x = 0; x < nx; ++x) edge(x);
    return;
  }
  const double half_force = has_force_ ? 0.5 * plans_.for_row(y, z).force[0] : 0.0;
  edge(0);
  for_each_interior_block<1>(y, z, 1, nx - 1, [&](int, int n, const double* drho, const auto& j) {
    for (int k = 0; k < n; ++k) sum += (j[0][k] + half_force) / (config_.rho0 + drho[k]);
  });
  edge(nx - 1);
}

template <class L, class T>
void FluidLattice<L, T>::row_moments(int y, int z, int first, int count, double* density, double* velocity) const {
  const int nx = config_.nx;
  const auto store = [&](int x, const Moments& m) {
    const long k = x - first;
    if (density) density[k] = m.rho;
    if (velocity)
      for (int a = 0; a < 3; ++a) velocity[3 * k + a] = m.u[a];
  };
  const int inner_first = std::max(first, 1), inner_end = std::min(first + count, nx - 1);
  if (inner_first >= inner_end) {  // edge nodes only
    for (int x = first; x < first + count; ++x) store(x, moments(x, y, z));
    return;
  }
  if (first == 0) store(0, moments(0, y, z));
  const auto& force = plans_.for_row(y, z).force;
  double half_force[3];
  for (int a = 0; a < 3; ++a) half_force[a] = has_force_ ? 0.5 * force[a] : 0.0;
  for_each_interior_block<3>(y, z, inner_first, inner_end, [&](int x, int n, const double* drho, const auto& j) {
    for (int k = 0; k < n; ++k) {
      const long at = x + k - first;
      const double rho = config_.rho0 + drho[k];
      if (density) density[at] = rho;
      if (velocity)
        for (int a = 0; a < 3; ++a) velocity[3 * at + a] = (j[a][k] + half_force[a]) / rho;
    }
  });
  if (first + count == nx) store(nx - 1, moments(nx - 1, y, z));
}

template <class L, class T>
std::array<double, L::Q> FluidLattice<L, T>::populations(int x, int y, int z) const {
  const auto g = gather(x, y, z);
  std::array<double, Q> f;
  for (int i = 0; i < Q; ++i) f[i] = static_cast<double>(g[i]) + L::w[i] * config_.rho0;
  return f;
}

template <class L, class T>
double FluidLattice<L, T>::total_mass() const {
  double drho = 0;
  for (int z = 0; z < config_.nz; ++z)
    for (int y = 0; y < config_.ny; ++y)
      for (int x = 0; x < config_.nx; ++x)
        for (T g : gather(x, y, z)) drho += g;
  return config_.rho0 * static_cast<double>(cells_) + drho;
}

template <class L, class T>
Vec3 FluidLattice<L, T>::total_momentum() const {
  Vec3 p{0, 0, 0};
  for (int z = 0; z < config_.nz; ++z)
    for (int y = 0; y < config_.ny; ++y)
      for (int x = 0; x < config_.nx; ++x) {
        const auto g = gather(x, y, z);
        for (int i = 0; i < Q; ++i)
          for (int a = 0; a < 3; ++a) p[a] += L::c[i][a] * static_cast<double>(g[i]);
      }
  return p;
}

template <class L, class T>
Vec3 FluidLattice<L, T>::position(int x, int y, int z) {
  const double shift = L::hexagonal ? 0.5 * (y & 1) : 0.0;
  return {x + shift, y * L::row_spacing, static_cast<double>(z)};
}

}  // namespace lbsolid::fluid
