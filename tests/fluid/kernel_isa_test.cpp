// The fluid kernels are compiled for three instruction sets and each step runs the best the CPU
// has (fluid/kernel_isa.h). A binary then gives the same results on every x86-64 machine only if
// every path computes the same thing bit for bit: run each path this CPU has on the same walled,
// forced box, for every collision, streaming scheme and precision, and compare every population.
#include <gtest/gtest.h>

#include <vector>

#include "fluid/fluid_test_support.h"
#include "fluid/kernel_isa.h"

namespace lbsolid::testing {
namespace {

using fluid::CollisionModel;
using fluid::KernelIsa;
using fluid::StreamingScheme;

template <class L>
FluidConfig forced_walled_box(CollisionModel collision, StreamingScheme streaming) {
  FluidConfig c = channel_config<L>(11, WallKind::kFreeSlip, WallKind::kBounceBack, 1.7);
  c.nx = 37;  // not a multiple of any vector width: remainders and row ends run too
  c.nz = L::D == 3 ? 5 : 1;
  c.sides[fluid::kYLow].traction = {2e-4, 0, 0};
  c.body_force = {1e-5, -2e-5, L::D == 3 ? 1e-5 : 0.0};
  c.collision = collision;
  c.streaming = streaming;
  return c;
}

// Every population after 23 steps (odd: in place ends on a pulling step) on the given path.
template <class L, class T>
std::vector<double> populations_after_steps(const FluidConfig& c, KernelIsa isa) {
  KernelIsaLimit limit(isa);
  FluidLattice<L, T> fluid(c);
  fluid.initialize([](int x, int y, int z) { return 1.0 + 0.002 * std::sin(0.9 * x + 0.4 * y - 0.3 * z); },
                   [](int x, int y, int z) { return Vec3{0.03 * std::cos(0.5 * y), 0.01 * std::sin(0.7 * x), 0.005 * z}; });
  fluid.run(23);
  return every_population(fluid);
}

template <class L, class T>
void expect_every_path_alike() {
  const KernelIsa best = fluid::kernel_isa();
  for (CollisionModel collision : {CollisionModel::kBgk, CollisionModel::kTrt, CollisionModel::kRegularized})
    for (StreamingScheme streaming : {StreamingScheme::kInPlace, StreamingScheme::kTwoBuffer}) {
      const FluidConfig c = forced_walled_box<L>(collision, streaming);
      const std::vector<double> baseline = populations_after_steps<L, T>(c, KernelIsa::kBaseline);
      for (KernelIsa isa : {KernelIsa::kAvx2, KernelIsa::kAvx512}) {
        if (isa > best) continue;  // a path this CPU cannot run
        const std::vector<double> other = populations_after_steps<L, T>(c, isa);
        ASSERT_EQ(other.size(), baseline.size());
        for (std::size_t k = 0; k < baseline.size(); ++k)
          ASSERT_EQ(other[k], baseline[k]) << fluid::kernel_isa_name(isa) << " against baseline, collision "
                                           << static_cast<int>(collision) << ", streaming "
                                           << static_cast<int>(streaming) << ", population " << k;
      }
    }
}

TEST(KernelIsa, EveryPathGivesTheBaselinesPopulationsD2Q9) {
  expect_every_path_alike<D2Q9, double>();
  expect_every_path_alike<D2Q9, float>();
}
TEST(KernelIsa, EveryPathGivesTheBaselinesPopulationsD2Q7) {
  expect_every_path_alike<D2Q7, double>();
  expect_every_path_alike<D2Q7, float>();
}
TEST(KernelIsa, EveryPathGivesTheBaselinesPopulationsD3Q19) {
  expect_every_path_alike<D3Q19, double>();
  expect_every_path_alike<D3Q19, float>();
}

// A limit lowers the path and never raises it past what the CPU has.
TEST(KernelIsa, ALimitLowersThePathAndNeverRaisesIt) {
  const KernelIsa best = fluid::kernel_isa();
  {
    KernelIsaLimit limit(KernelIsa::kBaseline);
    EXPECT_EQ(fluid::kernel_isa(), KernelIsa::kBaseline);
  }
  EXPECT_EQ(fluid::kernel_isa(), best);
  fluid::limit_kernel_isa(KernelIsa::kAvx512);
  EXPECT_LE(fluid::kernel_isa(), best);
  EXPECT_STREQ(fluid::kernel_isa_name(KernelIsa::kAvx2), "avx2");
}

}  // namespace
}  // namespace lbsolid::testing
