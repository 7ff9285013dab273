// The solid's step sums each particle's momentum Psi_p = sum_k f_k(p) while it streams, a block
// behind the particles it advances, and sums what lies near the ends of each part after all parts
// (SolidSystem::stream). These tests check that against the definition, recomputed here from the
// stored vectors, and that the step gives the same state bit for bit for any number of parts,
// with bodies whose labels are in scrambled order (senders far apart in index order) beside
// compact ones, and after links broke and a particle was shed; and that a step, which replaces
// the link vectors in place, gives what eqs. 6-7 give with a second buffer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <mutex>
#include <string>
#include <random>
#include <vector>

#include "parallel/thread_pool.h"
#include "solid/body_shape.h"
#include "solid/solid_system.h"

namespace lbsolid::solid {
namespace {

// A wide sheet (senders up to its width apart, or its width times its height in 3D), a chain and,
// with `scrambled`, the same sheet with its labels shuffled (senders anywhere in that body: the
// step then sums most particles after streaming).
SolidSystem make_solid(int dimension, bool scrambled) {
  SolidSystem solid(dimension);
  BodySpec sheet;
  sheet.size = {37, 9, dimension == 3 ? 4 : 1};
  solid.add_body("sheet", body_labels(sheet, dimension), 1.0, {30, 10, dimension == 3 ? 5.0 : 0.0},
                 {0.01, -0.02, 0}, {0, 0, 0});
  BodySpec chain;
  chain.shape = BodyShape::kChain;
  chain.length = 300;
  solid.add_body("chain", body_labels(chain, dimension), 0.9, {200, 70, 0}, {0, 0.01, 0}, {0, 0, 0});
  if (scrambled) {
    auto labels = body_labels(sheet, dimension);
    std::shuffle(labels.begin(), labels.end(), std::mt19937_64(7));
    solid.add_body("scrambled", labels, 1.0, {30, 40, 0}, {-0.01, 0, 0}, {0, 0, 0});
  }
  return solid;
}

// Random loads, the same for every run of a given seed: the step reads each once, as it reaches
// its particle.
std::vector<Vec3> loads(int n, int dimension, int step) {
  std::mt19937_64 rng(1000 + step);
  std::uniform_real_distribution<double> load(-0.01, 0.01);
  std::vector<Vec3> force(n);
  for (Vec3& f : force)
    for (int a = 0; a < dimension; ++a) f[a] = load(rng);
  return force;
}

// Psi_p as MODEL.md defines it, summed here in link order from what the solid stores.
void expect_momentum_is_sum_of_incoming(const SolidSystem& solid, int step) {
  for (int p = 0; p < solid.particle_count(); ++p) {
    Vec3 sum{0, 0, 0};
    for (int k = 0; k < solid.topology().links(); ++k)
      for (int a = 0; a < 3; ++a) sum[a] += solid.incoming(p, k)[a];
    ASSERT_EQ(solid.momentum(p), sum) << "particle " << p << " after step " << step;
  }
}

// Runs `steps` steps cut into `parts` (no pool for 1), breaking links and shedding the chain's
// first particle half-way, and returns the final state.
SolidState run(int dimension, bool scrambled, int parts, int steps) {
  SolidSystem solid = make_solid(dimension, scrambled);
  parallel::ThreadPool pool(3);
  for (int step = 1; step <= steps; ++step) {
    if (step == steps / 2) {
      const int chain_start = solid.body(1).first;
      solid.break_link(chain_start, 0, step);  // the chain's first particle loses its only link
      solid.shed(chain_start, solid.momentum(chain_start));
      solid.break_link(solid.body(0).first + 40, 1, step);  // two links inside the sheet
      solid.break_link(solid.body(0).first + 41, 0, step);
    }
    solid.step(loads(solid.particle_count(), dimension, step), parts > 1 ? &pool : nullptr, parts);
    expect_momentum_is_sum_of_incoming(solid, step);
  }
  return solid.state();
}

void expect_same_state(const SolidState& a, const SolidState& b, int parts) {
  EXPECT_EQ(a.positions, b.positions) << parts << " parts";
  EXPECT_EQ(a.incoming, b.incoming) << parts << " parts";
  EXPECT_EQ(a.momentum, b.momentum) << parts << " parts";
}

void check_parts(int dimension) {
  constexpr int kSteps = 40;
  for (bool scrambled : {false, true}) {
    SCOPED_TRACE(scrambled ? "with a scrambled body" : "compact bodies");
    const SolidState one = run(dimension, scrambled, 1, kSteps);
    // Parts many times a sheet's row, a few rows, and shorter than a row (most parts then have no
    // interior: every particle is summed after the stream).
    for (int parts : {2, 3, 7, 30, 1000}) expect_same_state(one, run(dimension, scrambled, parts, kSteps), parts);
  }
}

// What a step shows the caller as it goes (stream with a PositionsSeen, for the coupling's next
// nodes): every particle once, in blocks that run in order through ranges covering all
// particles, each range finished once after its last block, and a particle's position when seen
// is its position after the step.
struct SeenBlocks {
  struct Block {
    int first, end;
    std::vector<double> positions;  // as seen
  };
  struct Ranges {
    std::mutex mutex;
    std::vector<std::vector<Block>> finished;
    int unfinished = 0;
  };
  const SolidSystem* solid;
  Ranges* ranges;
  struct Range {
    const SeenBlocks* of;
    std::vector<Block> blocks;
    void operator()(int first, int end) {
      const ParticleVectors r = of->solid->positions();
      blocks.push_back({first, end, {r.data + static_cast<std::size_t>(first) * r.dimension,
                                     r.data + static_cast<std::size_t>(end) * r.dimension}});
    }
    void finish() {
      std::lock_guard lock(of->ranges->mutex);
      of->ranges->finished.push_back(std::move(blocks));
      --of->ranges->unfinished;
    }
  };
  Range range() const {
    std::lock_guard lock(ranges->mutex);
    ++ranges->unfinished;
    return {this, {}};
  }
};

TEST(SolidStreamParts, ShowsEachNewPositionOnceInOrderedBlocks) {
  parallel::ThreadPool pool(3);
  for (int dimension : {2, 3})
    for (int parts : {1, 2, 3, 1000}) {
      SCOPED_TRACE(std::to_string(dimension) + "D, " + std::to_string(parts) + " parts");
      SolidSystem solid = make_solid(dimension, /*scrambled=*/true);
      SeenBlocks::Ranges ranges;
      const std::uint64_t before = solid.positions_version();
      const std::vector<Vec3> force = loads(solid.particle_count(), dimension, 1);
      solid.stream([&](int p) { return force[p]; }, SeenBlocks{&solid, &ranges}, parts > 1 ? &pool : nullptr, parts);
      EXPECT_NE(solid.positions_version(), before);
      EXPECT_EQ(ranges.unfinished, 0);
      std::vector<int> seen(solid.particle_count(), 0);
      const ParticleVectors after = solid.positions();
      for (const auto& blocks : ranges.finished) {
        ASSERT_FALSE(blocks.empty());
        for (std::size_t b = 0; b < blocks.size(); ++b) {
          if (b > 0) ASSERT_EQ(blocks[b].first, blocks[b - 1].end);  // in order, none skipped
          for (int p = blocks[b].first; p < blocks[b].end; ++p) {
            ++seen[p];
            for (int a = 0; a < dimension; ++a)
              ASSERT_EQ(blocks[b].positions[static_cast<std::size_t>(p - blocks[b].first) * dimension + a],
                        after.data[static_cast<std::size_t>(p) * dimension + a])
                  << "particle " << p;
          }
        }
      }
      for (int p = 0; p < solid.particle_count(); ++p) ASSERT_EQ(seen[p], 1) << "particle " << p;
      // A step moves the particles (each has a velocity): the positions seen are the new ones.
      EXPECT_NE(solid.state().positions, make_solid(dimension, true).state().positions);
    }
}

// One step against eqs. 6-7 as MODEL.md writes them, worked out here with a second buffer from
// the state before the step: f_k(p + c_k) <- Psi_p/M_p + F_p/(2 M_p) - f_opp(k)(p), r_p moved by
// the same base. The solid replaces each link's two vectors in place, in an order of its own, and
// must give the same values. The bound: the reference divides where the solid multiplies by 1/M
// (round-off, about 1e-17 on values of 1e-2); using a vector already replaced, or the wrong one,
// errs by the size of a vector or a load, 1e-3 or more.
void check_one_step_against_the_wave_rule(int dimension, int parts) {
  SolidSystem solid = make_solid(dimension, /*scrambled=*/true);
  parallel::ThreadPool pool(3);
  const int n = solid.particle_count(), links = solid.topology().links();
  for (int step = 1; step <= 3; ++step) {
    const std::vector<Vec3> force = loads(n, dimension, step);
    std::vector<Vec3> expected_incoming(static_cast<std::size_t>(n) * links, Vec3{0, 0, 0});
    std::vector<Vec3> expected_position(n);
    for (int p = 0; p < n; ++p) {
      const double m = solid.mass(p);
      Vec3 base{0, 0, 0};
      for (int a = 0; a < 3; ++a) base[a] = solid.momentum(p)[a] / m + force[p][a] / (2 * m);
      for (int a = 0; a < 3; ++a) expected_position[p][a] = solid.position(p)[a] + base[a];
      for (int k = 0; k < links; ++k) {
        const int q = solid.neighbour(p, k);
        if (q < 0) continue;
        const Vec3 back = solid.incoming(p, solid.topology().opposite(k));
        for (int a = 0; a < 3; ++a) expected_incoming[static_cast<std::size_t>(q) * links + k][a] = base[a] - back[a];
      }
    }
    solid.step(force, parts > 1 ? &pool : nullptr, parts);
    constexpr double kRoundOff = 1e-14;
    for (int p = 0; p < n; ++p) {
      for (int a = 0; a < 3; ++a) ASSERT_NEAR(solid.position(p)[a], expected_position[p][a], kRoundOff) << p;
      for (int k = 0; k < links; ++k)
        for (int a = 0; a < 3; ++a)
          ASSERT_NEAR(solid.incoming(p, k)[a], expected_incoming[static_cast<std::size_t>(p) * links + k][a], kRoundOff)
              << "particle " << p << " link " << k << " after step " << step << ", " << parts << " parts";
    }
    expect_momentum_is_sum_of_incoming(solid, step);
  }
}

TEST(SolidStreamParts, OneStepIsTheWaveRuleAsWritten) {
  for (int dimension : {2, 3})
    for (int parts : {1, 3, 1000}) check_one_step_against_the_wave_rule(dimension, parts);
}

TEST(SolidStreamParts, MomentumIsTheSumOfWhatArrivedAndPartsDoNotChangeTheRun2D) { check_parts(2); }
TEST(SolidStreamParts, MomentumIsTheSumOfWhatArrivedAndPartsDoNotChangeTheRun3D) { check_parts(3); }

}  // namespace
}  // namespace lbsolid::solid
