#pragma once
#include <algorithm>

#include "fluid/force_inline.h"

namespace lbsolid::fluid {

// Calls update(begin, end) for cells [begin, end) cut where a cell's slots start a cache line
// (every array is line-aligned and a whole number of lines long): the long part's vectors then
// load and store whole lines in every stream whose offset is a multiple of a line. A vector
// straddling two lines costs about twice as much (measured: D3Q19's local step over 121^3
// doubles 87 MLUPS with its rows' runs starting off a line, 163 at 96^3 where they start on one).
template <class T, class Update>
LBSOLID_FORCE_INLINE void for_line_aligned_parts(long begin, long end, Update&& update) {
  constexpr long kLine = 64 / static_cast<long>(sizeof(T));
  const long cuts[3] = {begin, std::min(end, (begin + kLine - 1) / kLine * kLine), end};
  for (int part = 0; part < 2; ++part)  // one call site: the update is compiled once
    if (cuts[part] < cuts[part + 1]) update(cuts[part], cuts[part + 1]);
}

}  // namespace lbsolid::fluid
