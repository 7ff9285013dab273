#pragma once
// In-place streaming on one buffer (the AA pattern, Bailey et al. 2009): two fused kernels that
// alternate, each reading and writing the same slots, so no second buffer is needed and every
// cache line a cell reads is the one it writes back.
//
//   even step: a cell reads its own slots f_i = A[i][x], collides, and writes each result reversed
//              into its own cell, A[opp(i)][x] = f*_i. No neighbour is touched.
//   odd step:  a cell pulls through the row plan: population k comes from f*_j at node s, which
//              the even step left in A[opp(j)][s]. After colliding it writes f*_k into the slot it
//              read for opp(k), through that entry's wall rule; that slot is where the next
//              even step finds the population arriving downstream. The wall rules are involutions,
//              so the slots a cell reads are exactly the slots it writes and cells never collide
//              (FluidLattice checks this once per configuration).
//
// Given a FinishedCells (in_step_exchange.h), each kernel reports the cells whose post-collision
// populations are stored for good, a row (or part of one) at a time, as soon as it can.
#include <type_traits>

#include "fluid/cell_update.h"
#include "fluid/force_inline.h"
#include "fluid/in_step_exchange.h"
#include "fluid/kernel_isa.h"
#include "fluid/shifted_pull.h"
#include "fluid/line_aligned_parts.h"
#include "fluid/row_plan.h"
#include "lattice/lattice_traits.h"

namespace lbsolid::fluid {

template <class L, class T, class Collision, bool kForce>
LBSOLID_FORCE_INLINE void collide_local_rows(const RowPlans<L, T>& plans, T* f, long stride, int nx,
                        long row_begin, long row_end, typename Collision::Rates rates, T rho0,
                        FinishedCells* finished = nullptr) {
  constexpr int Q = L::Q;
  constexpr auto opp = lattice::opposite_table<L>();
  const T* in[Q];
  T* out[Q];
  for (int i = 0; i < Q; ++i) {
    in[i] = f + i * stride;
    out[i] = f + opp[i] * stride;
  }
  constexpr auto no_wall = WallMap<T, Q>::identity();
  for (long first = row_begin; first < row_end;) {
    // This step reads no neighbour, so rows that share a force are one run of cells.
    const long last = plans.last_row_sharing_force(first, row_end);
    const RowPlan<T, Q>& plan = plans.for_row(first);
    const T force[3] = {plan.force[0], plan.force[1], plan.force[2]};
    // Reporting, a row with nodes alone (reported while its lines are in the cache) and the rows
    // between such rows at once; else the run at once.
    for (long row = first; row <= last;) {
      long end_row = last + 1;
      if (finished) {
        end_row = row + 1;
        if (!finished->row_has_nodes(row))
          while (end_row <= last && !finished->row_has_nodes(end_row)) ++end_row;
      }
      for_line_aligned_parts<T>(row * nx, end_row * nx, [&](long begin, long end) LBSOLID_FORCE_INLINE_LAMBDA {
        update_cells<L, T, Collision, kForce, false>(in, no_wall, out, no_wall, force, rates, rho0, begin, end);
      });
      if (finished && end_row == row + 1) (*finished)(row * nx, end_row * nx);
      row = end_row;
    }
    first = last + 1;
  }
}

// Where the pulling step's cells with one set of sources read and write: population k from the
// slot its source names, written back (as population opp(k)) into the slot read for opp(k),
// through that entry's wall rule. Indexed by cell.
template <class L, class T>
struct InPlacePull {
  static constexpr int Q = L::Q;
  const T* in[Q];
  T* out[Q];
  WallMap<T, Q> in_map, out_map;
  LBSOLID_FORCE_INLINE InPlacePull(const PullSources<T, Q>& sources, T* f, long stride) {
    constexpr auto opp = lattice::opposite_table<L>();
    T* slot[Q];
    for (int k = 0; k < Q; ++k) {
      const auto& s = sources[k];
      slot[k] = f + opp[s.dir] * stride + s.delta;
      in[k] = slot[k];
      in_map.scale[k] = s.scale;
      in_map.shift[k] = s.correction;
    }
    for (int k = 0; k < Q; ++k) {
      out[k] = slot[opp[k]];
      out_map.scale[k] = in_map.scale[opp[k]];
      out_map.shift[k] = in_map.shift[opp[k]];
    }
  }
};

// Lanes of the vectors the pulling step's shifted sweep (shifted_pull.h) uses on each path: one
// register of the widest kind; none on the baseline path.
template <class T>
constexpr int shifted_pull_lanes(KernelIsa isa) {
  return isa == KernelIsa::kAvx512 ? 64 / sizeof(T) : (isa == KernelIsa::kAvx2 ? 32 / sizeof(T) : 0);
}

// Where pull_joined_rows joins row r to row r + 1, its line's cells (nx - 1, r) and (0, r + 1)
// read, between them, the true sources of edge cells: each x-wrapped source is one row on in the
// line. Edge cell (0, r) reads its populations with c_x = +1 where line cell (0, r + 1) reads
// them and the rest where line cell (0, r) does; edge cell (nx - 1, r) reads those with c_x = -1
// where line cell (nx - 1, r - 1) does and the rest where line cell (nx - 1, r) does. So on D3Q19
// the sweep copies those two cells' inputs as it reaches each join, while their lines are in the
// cache, and the edge cells of all rows but the first and the last collide from the copies.
// Gathered from memory ahead of the sweep instead, each edge cell waited for 19 lines: 19% of
// the double pulling step at 128^3, 34% of the float one at 96^3, for 2% of the cells. This holds
// where the edge cells' sources are the line's so shifted, with no wall rule:
template <class L, class T>
bool edges_read_at_joins(const InPlacePull<L, T>& line, const InPlacePull<L, T> (&edges)[2], int nx) {
  for (const auto& edge : edges)
    if (!edge.in_map.is_identity() || !edge.out_map.is_identity()) return false;
  for (int k = 0; k < L::Q; ++k) {
    const int cx = static_cast<int>(L::c[k][0]);
    if (edges[0].in[k] != line.in[k] + (cx == 1 ? nx : 0) || edges[1].in[k] + (cx == -1 ? nx : 0) != line.in[k])
      return false;
  }
  return true;
}

// The shifted sweep of the joined rows [first, last] over [vector_begin, vector_end), which must
// hold every join's two cells, copying their inputs just before it reaches them: line cell
// (nx - 1, r)'s into at_last[k][r - first], (0, r + 1)'s into at_first[k][r + 1 - first]. Reports
// the interior cells of rows first .. last - 2 as the sweep passes them (the cells before each
// join are done when it gets there).
template <class L, class T, bool kForce, int kLanes, long kRunRows>
LBSOLID_FORCE_INLINE void sweep_copying_joins(const InPlacePull<L, T>& line, const T (&force)[3], T omega, T rho0,
                                              int nx, long first, long last, long vector_begin, long vector_end,
                                              T (&at_last)[L::Q][kRunRows], T (&at_first)[L::Q][kRunRows],
                                              FinishedCells* finished) {
  using Shifted = ShiftedPull<L, T, kLanes>;
  long done = vector_begin;
  for (long r = first; r < last; ++r) {
    const long join = (r + 1) * nx;                    // line cell (0, r + 1)
    const long before = (join - 1) / kLanes * kLanes;  // the vector holding line cell (nx - 1, r)
    if (before > done) {
      Shifted::template run<kForce>(line.in, line.out, force, omega, rho0, done, before);
      done = before;
    }
    if (finished && r > first) (*finished)((r - 1) * nx + 1, r * nx - 1);
    for (int k = 0; k < L::Q; ++k) {
      at_last[k][r - first] = line.in[k][join - 1];
      at_first[k][r + 1 - first] = line.in[k][join];
    }
  }
  Shifted::template run<kForce>(line.in, line.out, force, omega, rho0, done, vector_end);
}

// The pulling step over rows [first, last], sharing one plan, of a grid periodic in x, with BGK:
// false (nothing done) where the shifted sweep does not apply.
//
// The rows are swept as one line of cells, from the second cell of the first row to the
// last-but-one of the last, so that the shifted sweep's vectors run the whole line but for a
// vector and a bit at each end. In that line the last cell of a row and the first of the next
// read and write each other's slots instead of their own wrapped ones. Each slot still belongs to
// one cell of the line (every array is read at one fixed offset), so the sweep is race-free and
// right for every other cell; and every slot those edge cells touch belongs to some edge cell of
// the same rows (the rows' slots, less the other cells'). So the edge cells are computed first,
// from slots nothing has written yet, into a buffer, and written over what the line left there.
template <class L, class T, class Collision, bool kForce, int kLanes, long kRunRows>
LBSOLID_FORCE_INLINE bool pull_joined_rows(const RowPlans<L, T>& plans, T* f, long stride, int nx, long first,
                                           long last, T omega, T rho0, FinishedCells* finished) {
  constexpr int Q = L::Q;
  using Shifted = ShiftedPull<L, T, kLanes>;
  const RowPlan<T, Q>& plan = plans.for_row(first);
  const InPlacePull<L, T> line(plan.sources[1], f, stride);
  const long begin = first * nx + 1, end = last * nx + nx - 1;
  const long vector_begin = Shifted::first_cell(begin), vector_end = Shifted::end_cell(end);
  // On D3Q19 the cells the aligned sweep leaves (the line's ends, each row's edge cells) are done
  // as vectors too: one by one they took 40% of the float step at 48^3 (W = 16). Not on D2Q9: its
  // rows are long, and with that code in its kernel GCC spilled the line sweep's registers (the
  // pulling step at half speed, 1936^2 doubles).
  constexpr bool kVectorEnds = L::Q > 9;
  // Too short for the aligned sweep, a D3Q19 line of W cells or more is done with span() alone.
  const bool sweep = vector_begin < vector_end;
  const bool span_only = kVectorEnds && !sweep && end - begin >= kLanes;
  if ((!sweep && !span_only) || !line.in_map.is_identity() || !Shifted::streams_fit(line.in, line.out))
    return false;
  const T force[3] = {plan.force[0], plan.force[1], plan.force[2]};
  const InPlacePull<L, T> edges[2] = {{plan.sources[0], f, stride}, {plan.sources[2], f, stride}};
  // Population k of row r's edge cell on `side`, after collision: edge[side][k][r - first].
  alignas(64) T edge[2][Q][kRunRows];
  // The inputs of the line cells at each join, when the edge cells collide from them (above):
  // then the edge cells of the first and the last row alone are read here, before the sweep.
  const bool from_joins = kVectorEnds && sweep && nx >= 3 * kLanes && last - first - 1 >= kLanes &&
                          edges_read_at_joins(line, edges, nx);
  alignas(64) T at_last[Q][kRunRows], at_first[Q][kRunRows];
  for (int side = 0; side < 2; ++side) {
    const InPlacePull<L, T>& p = edges[side];
    const long x = side == 0 ? 0 : nx - 1;
    // On D3Q19, kLanes rows' edge cells at a time in a vector's lanes where no wall rule applies
    // and there are kLanes rows or more, else one by one. The last vector of rows ends at `last`
    // and may share rows with the one before: both read slots nothing has written yet, so those
    // rows get the same results twice (in the buffer).
    const bool columns =
        kVectorEnds && !from_joins && p.in_map.is_identity() && p.out_map.is_identity() && last - first + 1 >= kLanes;
    for (long row = first; row <= last;) {
      const long at = columns && row + kLanes - 1 > last ? last - kLanes + 1 : row;
      const T* in[Q];
      T* into[Q];
      for (int k = 0; k < Q; ++k) {
        in[k] = p.in[k] + at * nx + x;
        into[k] = &edge[side][k][at - first];
      }
      if constexpr (kVectorEnds) {
        if (columns) {
          Shifted::template column<kForce>(in, nx, into, force, omega, rho0);
          row = at + kLanes;
          continue;
        }
      }
      update_corrected_cells<L, T, Collision, kForce>(in, p.in_map, into, p.out_map, force, omega, rho0, 0, 1);
      row = from_joins && row == first ? last : row + 1;
    }
  }
  // The line's first and last W to 2W - 1 cells: on D3Q19 as unaligned vectors, else one by one.
  if constexpr (kVectorEnds) {
    if (span_only) {
      Shifted::template span<kForce>(line.in, line.out, force, omega, rho0, begin, end);
    } else {
      Shifted::template span<kForce>(line.in, line.out, force, omega, rho0, begin, vector_begin);
      if (from_joins) {
        sweep_copying_joins<L, T, kForce, kLanes, kRunRows>(line, force, omega, rho0, nx, first, last, vector_begin,
                                                            vector_end, at_last, at_first, finished);
        // The edge cells of rows first + 1 .. last - 1 (n of them, at least W), W rows at a time.
        const long n = last - first - 1;
        for (int side = 0; side < 2; ++side) {
          const T* in[Q];
          T* into[Q];
          for (int k = 0; k < Q; ++k) {
            const int cx = static_cast<int>(L::c[k][0]);
            in[k] = side == 0 ? &at_first[k][cx == 1 ? 2 : 1] : &at_last[k][cx == -1 ? 0 : 1];
            into[k] = &edge[side][k][1];
          }
          Shifted::template span<kForce>(in, into, force, omega, rho0, 0, n);
        }
      } else {
        Shifted::template run<kForce>(line.in, line.out, force, omega, rho0, vector_begin, vector_end);
      }
      Shifted::template span<kForce>(line.in, line.out, force, omega, rho0, vector_end, end);
      if (finished && from_joins)  // the interior cells the sweep did not report
        for (long row = last - 1; row <= last; ++row) (*finished)(row * nx + 1, row * nx + nx - 1);
    }
  } else {
    update_cells<L, T, Collision, kForce, false>(line.in, line.in_map, line.out, line.out_map, force, omega, rho0, begin,
                                                 vector_begin);
    Shifted::template run<kForce>(line.in, line.out, force, omega, rho0, vector_begin, vector_end);
    update_cells<L, T, Collision, kForce, false>(line.in, line.in_map, line.out, line.out_map, force, omega, rho0,
                                                 vector_end, end);
  }
  for (long row = first; row <= last; ++row)
    for (int side = 0; side < 2; ++side) {
      const long cell = row * nx + (side == 0 ? 0 : nx - 1);
      for (int k = 0; k < Q; ++k) edges[side].out[k][cell] = edge[side][k][row - first];
    }
  if (finished) {  // the edge cells, or (not swept row by row) the whole rows
    const bool reported_interior = kVectorEnds && from_joins;
    for (long row = first; row <= last; ++row) {
      if (reported_interior) {
        (*finished)(row * nx, row * nx + 1);
        (*finished)(row * nx + nx - 1, row * nx + nx);
      } else {
        (*finished)(row * nx, row * nx + nx);
      }
    }
  }
  return true;
}

template <class L, class T, class Collision, bool kForce, int kLanes = 0>
LBSOLID_FORCE_INLINE void stream_collide_in_place_rows(const RowPlans<L, T>& plans, T* f, long stride, int nx,
                                  long row_begin, long row_end, typename Collision::Rates rates, T rho0,
                                  FinishedCells* finished = nullptr) {
  constexpr bool kShifted =
      kLanes > 0 && std::is_same_v<Collision, BgkCollision<L, T>> && ShiftedPull<L, T, kLanes>::kLatticeFits;
  // Bounds the edge buffer: kRunRows x 2 x Q values (19 KB for D3Q19 double). D3Q19's rows are
  // short, so it joins up to 64 of them, and single rows too (their edges as one-by-one cells);
  // D2Q9 as before (32, and single rows through the row loop below).
  constexpr long kRunRows = L::Q > 9 ? 64 : 32;
  constexpr long kFewestRows = L::Q > 9 ? 1 : 2;
  for (long first = row_begin; first < row_end;) {
    long last = first;  // rows [first, last] are done together, else one by one
    if constexpr (kShifted) {
      if (plans.x_periodic() && nx > 2) {
        last = std::min(plans.last_row_sharing_plan(first, row_end), first + kRunRows - 1);
        if (last - first + 1 >= kFewestRows &&
            pull_joined_rows<L, T, Collision, kForce, kLanes, kRunRows>(plans, f, stride, nx, first, last, rates, rho0,
                                                                        finished)) {
          first = last + 1;
          continue;
        }
      }
    }
    for (long row = first; row <= last; ++row) {
      const auto& plan = plans.for_row(row);
      const T force[3] = {plan.force[0], plan.force[1], plan.force[2]};
      auto sweep = [&](int part, long begin, long end) LBSOLID_FORCE_INLINE_LAMBDA {
        const InPlacePull<L, T> p(plans.sources(row, part), f, stride);
        update_corrected_cells<L, T, Collision, kForce>(p.in, p.in_map, p.out, p.out_map, force, rates, rho0, begin,
                                                        end);
      };
      const long row_start = row * nx;
      sweep(0, row_start, row_start + 1);
      if (nx > 2) sweep(1, row_start + 1, row_start + nx - 1);
      if (nx > 1) sweep(2, row_start + nx - 1, row_start + nx);
      if (finished) (*finished)(row_start, row_start + nx);
    }
    first = last + 1;
  }
}

}  // namespace lbsolid::fluid
