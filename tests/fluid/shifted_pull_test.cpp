// The in-place pulling step's shifted sweep (fluid/shifted_pull.h) reads and writes the x-shifted
// streams as aligned vectors and shifts them in registers, over lines of rows joined end to end
// (fluid/in_place_kernel.h). It must give what the two-buffer kernel gives on the baseline path
// (which has no such sweep), bit for bit, on every path this CPU has: with rows whose length is
// a whole number of vectors (so that the sweep runs), walls in y and z (whose rows keep the plain
// sweep, beside rows that do not), a body force, one thread and three (parts that start anywhere).
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "fluid/fluid_test_support.h"
#include "fluid/in_place_kernel.h"
#include "fluid/kernel_isa.h"

namespace lbsolid::testing {
namespace {

using fluid::KernelIsa;
using fluid::StreamingScheme;

// nx = 64 (whole vectors of 2, 4, 8 and 16 lanes), ny = 34: 32 interior rows (y = 1 .. 32) share
// a plan, so D3Q19's rows' edge cells fill whole vectors of up to 16 lanes (and, with walls or 3
// threads' parts, leave rows over). nx = 48, ny = 47: 45 interior rows, so the last vector of
// edge cells shares rows with the one before, and with 16 lanes a single row's 46 interior cells
// are too few for the aligned sweep (done as unaligned vectors alone).
template <class L>
FluidConfig box(int nx, bool walled, int ny = 34) {
  FluidConfig c;
  c.nx = nx;
  c.ny = ny;
  c.nz = L::D == 3 ? 5 : 1;
  c.omega = 1.3;
  // This sweep is the arrays' (a periodic D3Q19 box would otherwise run in blocks on an AVX-512
  // host: blocked_layout_test.cpp).
  c.layout = fluid::PopulationLayout::kArrays;
  if (walled) {
    c.sides[fluid::kYLow].kind = c.sides[fluid::kYHigh].kind = WallKind::kBounceBack;
    if (L::D == 3) {
      c.sides[fluid::kZLow].kind = WallKind::kMovingWall;
      c.sides[fluid::kZLow].wall_velocity = {0.02, 0.01, 0};
      c.sides[fluid::kZHigh].kind = WallKind::kFreeSlip;
    }
    c.body_force = {2e-5, -1e-5, L::D == 3 ? 1e-5 : 0.0};
  }
  return c;
}

template <class L, class T>
std::vector<double> populations_after(FluidConfig c, StreamingScheme streaming, int threads, KernelIsa isa, long steps) {
  KernelIsaLimit limit(isa);
  c.streaming = streaming;
  c.threads = threads;
  FluidLattice<L, T> fluid(c);
  fluid.initialize([](int x, int y, int z) { return 1.0 + 0.002 * std::sin(0.9 * x + 0.4 * y - 0.3 * z); },
                   [](int x, int y, int z) { return Vec3{0.03 * std::cos(0.5 * y + 0.2 * x), 0.01 * std::sin(0.7 * x), 0.004 * z}; });
  fluid.run(steps);
  return every_population(fluid);
}

template <class L, class T>
void expect_in_place_equals_two_buffer() {
  const KernelIsa best = fluid::kernel_isa();
  for (const auto& [nx, ny] : {std::pair{64, 34}, std::pair{48, 47}})
    for (bool walled : {false, true})
      for (long steps : {1L, 2L, 37L})  // ending after either kind of step
        for (int threads : {1, 3}) {
          const FluidConfig c = box<L>(nx, walled, ny);
          // The baseline path has no shifted sweep. With the moving wall in place and two-buffer
          // differ in the last bit from the start (streaming_scheme_test.cpp), so they are held
          // against each other on the periodic box only.
          const auto reference = populations_after<L, T>(c, StreamingScheme::kInPlace, 1, KernelIsa::kBaseline, steps);
          if (!walled) {
            ASSERT_EQ(reference, (populations_after<L, T>(c, StreamingScheme::kTwoBuffer, 1, KernelIsa::kBaseline, steps)));
          }
          for (KernelIsa isa : {KernelIsa::kBaseline, KernelIsa::kAvx2, KernelIsa::kAvx512}) {
            if (isa > best) continue;  // a path this CPU cannot run
            const auto in_place = populations_after<L, T>(c, StreamingScheme::kInPlace, threads, isa, steps);
            ASSERT_EQ(in_place.size(), reference.size());
            for (std::size_t k = 0; k < reference.size(); ++k)
              ASSERT_EQ(in_place[k], reference[k]) << fluid::kernel_isa_name(isa) << (walled ? ", walled" : ", periodic")
                                                   << ", " << steps << " steps, " << threads << " threads, population "
                                                   << k;
          }
        }
}

TEST(ShiftedPull, InPlaceEqualsTwoBufferBitForBitD3Q19Double) { expect_in_place_equals_two_buffer<D3Q19, double>(); }
TEST(ShiftedPull, InPlaceEqualsTwoBufferBitForBitD3Q19Float) { expect_in_place_equals_two_buffer<D3Q19, float>(); }
TEST(ShiftedPull, InPlaceEqualsTwoBufferBitForBitD2Q9Double) { expect_in_place_equals_two_buffer<D2Q9, double>(); }
TEST(ShiftedPull, InPlaceEqualsTwoBufferBitForBitD2Q9Float) { expect_in_place_equals_two_buffer<D2Q9, float>(); }

// The sweep runs only where the streams sit where its shifts expect them: the interior rows of
// the boxes above, on every vector width, and not where a row is no whole number of vectors.
template <class L, class T, int W>
bool interior_streams_fit(int nx) {
  const FluidConfig c = box<L>(nx, false);
  fluid::RowPlans<L, T> plans(c);
  fluid::PopulationStorage<T> storage(1, L::Q, static_cast<long>(c.nx) * c.ny * c.nz);
  const fluid::InPlacePull<L, T> line(plans.for_row(1).sources[1], storage.buffer(0), storage.stride());
  return fluid::ShiftedPull<L, T, W>::streams_fit(line.in, line.out);
}

TEST(ShiftedPull, TheSweepAppliesToRowsOfWholeVectorsOnly) {
  EXPECT_TRUE((interior_streams_fit<D3Q19, double, 8>(64)));
  EXPECT_TRUE((interior_streams_fit<D3Q19, double, 4>(64)));
  EXPECT_TRUE((interior_streams_fit<D3Q19, float, 16>(64)));
  EXPECT_TRUE((interior_streams_fit<D2Q9, double, 8>(64)));
  EXPECT_FALSE((interior_streams_fit<D3Q19, double, 8>(60)));  // 60: a row shift of 4 lanes
  EXPECT_FALSE((interior_streams_fit<D3Q19, float, 16>(40)));
}

}  // namespace
}  // namespace lbsolid::testing
