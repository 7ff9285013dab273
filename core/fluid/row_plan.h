#pragma once
// The pull sources of every population, precomputed per row class. Rows differ only in whether
// they touch a y or z side and (D2Q7) in their parity, and cells of a row only in whether they are
// the first, an interior or the last cell; so a handful of plans describes the whole grid and the
// fused kernel reads each population as `base[x] + correction` with no branch per cell.
// Open x sides differ from row to row (an inlet's profile): with one, the first and last cell of
// every row get sources of their own (sources(row, part)), and the rows still share the interior.
#include <array>
#include <vector>

#include "fluid/fluid_config.h"
#include "fluid/pull_source.h"

namespace lbsolid::fluid {

template <class T, int Q>
struct PullSource {
  int dir = 0;
  long delta = 0;  // source cell minus destination cell
  T correction = 0;
  T scale = 1;  // 0 at a pressure outlet (what enters there is set, not carried)
};

template <class T, int Q>
using PullSources = std::array<PullSource<T, Q>, Q>;

template <class T, int Q>
struct RowPlan {
  // [0] the first cell of the row, [1] interior cells, [2] the last cell.
  std::array<PullSources<T, Q>, 3> sources{};
  T force[3] = {0, 0, 0};  // body force plus the traction of an adjacent free-slip wall
  bool present = false;
};

template <class L, class T>
class RowPlans {
 public:
  static constexpr int Q = L::Q;
  RowPlans() = default;
  explicit RowPlans(const FluidConfig& cfg)
      : nx_(cfg.nx), ny_(cfg.ny), nz_(cfg.nz), x_periodic_(cfg.sides[kXLow].kind == WallKind::kPeriodic), plans_(32) {
    for (int z = 0; z < nz_; ++z) {
      for (int y = 0; y < ny_; ++y) {
        RowPlan<T, Q>& plan = plans_[key(y, z)];
        if (plan.present) continue;
        plan.present = true;
        for (int part = 0; part < 3; ++part) plan.sources[part] = resolve(cfg, part, y, z);
        Vec3 force = cfg.body_force;
        auto add_traction = [&](int side) {
          if (cfg.sides[side].kind != WallKind::kFreeSlip) return;
          for (int a = 0; a < 3; ++a) force[a] += cfg.sides[side].traction[a];
        };
        if (L::D >= 2 && y == 0) add_traction(kYLow);
        if (L::D >= 2 && y == ny_ - 1) add_traction(kYHigh);
        if (L::D == 3 && z == 0) add_traction(kZLow);
        if (L::D == 3 && z == nz_ - 1) add_traction(kZHigh);
        for (int a = 0; a < 3; ++a) plan.force[a] = static_cast<T>(force[a]);
      }
    }
    if (!is_open(cfg.sides[kXLow].kind) && !is_open(cfg.sides[kXHigh].kind)) return;
    const long rows = static_cast<long>(ny_) * nz_;
    edge_sources_.resize(2 * rows);
    for (long row = 0; row < rows; ++row) {
      const int y = static_cast<int>(row % ny_), z = static_cast<int>(row / ny_);
      edge_sources_[2 * row] = resolve(cfg, 0, y, z);
      edge_sources_[2 * row + 1] = resolve(cfg, 2, y, z);
    }
  }

  // The sources of the cells of `part` (part_of) of a row.
  const PullSources<T, Q>& sources(long row, int part) const {
    if (part != 1 && !edge_sources_.empty()) return edge_sources_[2 * row + part / 2];
    return for_row(row).sources[part];
  }
  const PullSources<T, Q>& sources(int x, int y, int z) const {
    return sources(y + static_cast<long>(ny_) * z, part_of(x, nx_));
  }
  // The same for row (y, z) given as coordinates: no division to find its plan.
  const PullSources<T, Q>& sources_of_part(int y, int z, int part) const {
    if (part != 1 && !edge_sources_.empty()) return edge_sources_[2 * (y + static_cast<long>(ny_) * z) + part / 2];
    return for_row(y, z).sources[part];
  }
  // Sets the correction of population i at the first (part 0) or last (part 2) cell of `row`:
  // a pressure outlet's follows the flow beside it (FluidLattice::refresh_outlet_corrections).
  void set_edge_correction(long row, int part, int i, T correction) {
    edge_sources_[2 * row + part / 2][i].correction = correction;
  }

  const RowPlan<T, Q>& for_row(int y, int z) const { return plans_[key(y, z)]; }
  // Rows are numbered as cells are (x fastest): row = y + ny z.
  const RowPlan<T, Q>& for_row(long row) const {
    return for_row(static_cast<int>(row % ny_), static_cast<int>(row / ny_));
  }
  // The last row of the run that starts at `first`, ends before `end` and shares first's plan.
  long last_row_sharing_plan(long first, long end) const {
    const RowPlan<T, Q>* plan = &for_row(first);
    long last = first;
    while (last + 1 < end && &for_row(last + 1) == plan) ++last;
    return last;
  }
  // The last row of the run that starts at `first`, ends before `end` and has first's force.
  long last_row_sharing_force(long first, long end) const {
    const T* force = for_row(first).force;
    long last = first;
    while (last + 1 < end) {
      const T* next = for_row(last + 1).force;
      if (next[0] != force[0] || next[1] != force[1] || next[2] != force[2]) break;
      ++last;
    }
    return last;
  }
  // Whether rows wrap around in x (both x sides periodic): a row's last cell is its first's upstream.
  bool x_periodic() const { return x_periodic_; }
  static int part_of(int x, int nx) { return x == 0 ? 0 : (x == nx - 1 ? 2 : 1); }
  long cell(int x, int y, int z) const {
    return x + static_cast<long>(nx_) * (y + static_cast<long>(ny_) * z);
  }

 private:
  // The sources of the first cell of the row (part 0), an interior one (1) or the last (2).
  PullSources<T, Q> resolve(const FluidConfig& cfg, int part, int y, int z) const {
    const int xs[3] = {0, nx_ > 2 ? 1 : 0, nx_ - 1};
    const long dest = cell(xs[part], y, z);
    PullSources<T, Q> sources;
    for (int i = 0; i < Q; ++i) {
      const PullSourceRule r = resolve_pull_source<L>(cfg, i, xs[part], y, z);
      sources[i] = {r.dir, cell(r.node[0], r.node[1], r.node[2]) - dest, static_cast<T>(r.correction),
                    static_cast<T>(r.scale)};
    }
    return sources;
  }
  int key(int y, int z) const {
    const int ycat = (y == 0 ? 1 : 0) | (y == ny_ - 1 ? 2 : 0);
    const int zcat = (z == 0 ? 1 : 0) | (z == nz_ - 1 ? 2 : 0);
    const int parity = L::hexagonal ? (y & 1) : 0;
    return (ycat * 4 + zcat) * 2 + parity;
  }
  int nx_ = 0, ny_ = 0, nz_ = 0;
  bool x_periodic_ = false;
  std::vector<RowPlan<T, Q>> plans_;
  std::vector<PullSources<T, Q>> edge_sources_;  // per row: [2 row] its first cell, [2 row + 1] its last
};

}  // namespace lbsolid::fluid
