#include "server/platform/huge_pages.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>

#include "fluid/population_block_advice.h"

namespace lbsolid::platform {

void advise_huge_pages(void* block, std::size_t bytes) {
  const long page_size = sysconf(_SC_PAGESIZE);
  if (page_size <= 0) return;
  const auto page = static_cast<std::uintptr_t>(page_size);
  const auto start = reinterpret_cast<std::uintptr_t>(block);
  const std::uintptr_t first = (start + page - 1) / page * page, end = (start + bytes) / page * page;
  // The result is not checked: on failure (EINVAL without THP) the pages stay small, which is the
  // state the block was in.
  if (end > first) madvise(reinterpret_cast<void*>(first), end - first, MADV_HUGEPAGE);
}

void use_huge_pages_for_populations(bool on) { fluid::set_population_block_advice(on ? &advise_huge_pages : nullptr); }

}  // namespace lbsolid::platform
