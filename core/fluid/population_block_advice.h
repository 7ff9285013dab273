#pragma once
// What a program may ask of the memory behind each population block before it is first touched.
// The populations are read as 2Q streams (19 arrays of 14 MB at 96^3 on D3Q19); with 4 KiB pages
// every stream crosses a page every 4 KiB, and the coupling's reads of a lone node touch Q pages.
// Linux can back such blocks with 2 MiB pages when asked (madvise), which core, plain C++, cannot
// do itself: a program that can (the daemon, the benchmarks: server/platform/huge_pages.h) sets an
// advice here once at start, and every PopulationStorage built after that calls it on its block.
#include <cstddef>

namespace lbsolid::fluid {

// Called with a freshly allocated, zeroed and not yet touched block; must leave its contents alone.
using PopulationBlockAdvice = void (*)(void* block, std::size_t bytes);

// Sets the advice (nullptr: none, the default). Safe to call from any thread.
void set_population_block_advice(PopulationBlockAdvice advice);
PopulationBlockAdvice population_block_advice();

}  // namespace lbsolid::fluid
