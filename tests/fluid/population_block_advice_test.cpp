// The page advice a program sets for population blocks (fluid/population_block_advice.h): each
// block a PopulationStorage allocates is handed to it once, whole, before any population is
// written; with none set nothing is called.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "fluid/population_block_advice.h"
#include "fluid/population_storage.h"

namespace lbsolid::fluid {
namespace {

struct Advised {
  void* block;
  std::size_t bytes;
  bool all_zero;  // nothing written to it yet
};
std::vector<Advised> advised;

void record(void* block, std::size_t bytes) {
  const auto* byte = static_cast<const unsigned char*>(block);
  bool zero = true;
  for (std::size_t k = 0; k < bytes; k += 4096) zero = zero && byte[k] == 0;  // a byte a page
  advised.push_back({block, bytes, zero});
}

TEST(PopulationBlockAdvice, EachBlockIsAdvisedWholeBeforeItIsWritten) {
  advised.clear();
  set_population_block_advice(&record);
  {
    PopulationStorage<double> two_buffers(2, 19, 5000);
    ASSERT_EQ(advised.size(), 1u);
    EXPECT_TRUE(advised[0].all_zero);
    // Every population of both buffers lies inside the advised block.
    const auto first = reinterpret_cast<std::uintptr_t>(advised[0].block);
    const auto end = first + advised[0].bytes;
    EXPECT_GE(reinterpret_cast<std::uintptr_t>(two_buffers.buffer(0)), first);
    EXPECT_LE(reinterpret_cast<std::uintptr_t>(two_buffers.buffer(1) + 19 * two_buffers.stride()), end);
    PopulationStorage<float> one_buffer(1, 9, 100);
    EXPECT_EQ(advised.size(), 2u);
  }
  set_population_block_advice(nullptr);
  PopulationStorage<double> unadvised(1, 9, 100);
  EXPECT_EQ(advised.size(), 2u) << "no advice set, none called";
  EXPECT_EQ(population_block_advice(), nullptr);
}

}  // namespace
}  // namespace lbsolid::fluid
