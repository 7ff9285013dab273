#pragma once
// Transparent huge pages for the fluid's population blocks (core/fluid/population_block_advice.h).
// With 4 KiB pages the D3Q19 kernel's 19 streams each cross a page every 4 KiB and a lone node's
// 19 populations lie on 19 pages: measured on this project's 2-core VM, asking Linux for 2 MiB
// pages made the D3Q19 step 23-36% faster (docs/performance.md).
#include <cstddef>

namespace lbsolid::platform {

// madvise(MADV_HUGEPAGE) on the whole pages inside [block, block + bytes). Advice only: where the
// kernel cannot (no THP support, "never" mode) the block stays as it was and works the same.
void advise_huge_pages(void* block, std::size_t bytes);

// Makes every population block built from now on ask for huge pages (or, with false, none).
void use_huge_pages_for_populations(bool on);

}  // namespace lbsolid::platform
