// The daemon's page advice (server/platform/huge_pages.h): a block it advises is marked for
// transparent huge pages in the kernel's own account of the mapping ("hg" among the VmFlags of
// /proc/self/smaps), and its contents are left as they were.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "fluid/population_block_advice.h"
#include "server/platform/huge_pages.h"

namespace lbsolid::platform {
namespace {

// The VmFlags line of the mapping that holds `address`, from /proc/self/smaps ("" if none).
std::string vm_flags_of(const void* address) {
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    std::uintptr_t first = 0, end = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> first >> dash >> end && dash == '-' && line.find(':') > line.find(' ')) {
      inside = at >= first && at < end;  // a mapping's header line: "first-end perms ..."
      continue;
    }
    if (inside && line.rfind("VmFlags:", 0) == 0) return line;
  }
  return "";
}

TEST(HugePages, AnAdvisedBlockIsMarkedForTheKernelAndKeepsItsContents) {
  // 64 MiB: above glibc's largest mmap threshold, so the block is a mapping of its own.
  const std::size_t bytes = std::size_t{64} << 20;
  auto* block = static_cast<unsigned char*>(std::calloc(bytes, 1));
  ASSERT_NE(block, nullptr);
  const std::string before = vm_flags_of(block + bytes / 2);
  ASSERT_FALSE(before.empty()) << "the block's mapping was not found in /proc/self/smaps";
  EXPECT_EQ(before.find(" hg"), std::string::npos) << before;
  for (std::size_t k = 0; k < bytes; k += 1 << 20) block[k] = static_cast<unsigned char>(1 + k % 251);
  advise_huge_pages(block, bytes);
  const std::string after = vm_flags_of(block + bytes / 2);
  EXPECT_NE(after.find(" hg"), std::string::npos) << after;
  for (std::size_t k = 0; k < bytes; k += 4096)
    ASSERT_EQ(block[k], k % (1 << 20) == 0 ? 1 + k % 251 : 0) << "byte " << k;
  std::free(block);
}

TEST(HugePages, TheSwitchSetsAndClearsThePopulationAdvice) {
  use_huge_pages_for_populations(true);
  EXPECT_EQ(fluid::population_block_advice(), &advise_huge_pages);
  use_huge_pages_for_populations(false);
  EXPECT_EQ(fluid::population_block_advice(), nullptr);
}

}  // namespace
}  // namespace lbsolid::platform
