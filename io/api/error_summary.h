#pragma once
// What a client is told about an invalid scenario: the first problems, then how many more.
// gRPC sends a status message as a percent-encoded header, and a client refuses headers over its
// metadata limit (8 KiB by default) with RESOURCE_EXHAUSTED, which clients take as "retry later":
// an invalid scenario with 130 problems was retried forever. Each byte outside printable ASCII
// takes 3 once encoded, so the summary is held to 2 KiB: 6 KiB on the wire at worst, leaving 2 KiB
// for the call's other headers. TranslatedScenario::errors keeps every problem for callers in
// process. Header-only because the API library is a single translation unit.
#include <cstddef>
#include <string>
#include <vector>

#include "io/api/log_text.h"

namespace lbsolid::server {

inline constexpr std::size_t kMaxSummaryProblems = 20;
inline constexpr std::size_t kMaxSummaryBytes = 2048;
// One problem is cut to this (no message of ours is as long; a core message it does not know may be).
inline constexpr std::size_t kMaxSummaryProblemBytes = 256;

// "p1; p2; ...; p20; ... and 130 more problems": the problems joined by "; " while there are at
// most kMaxSummaryProblems of them and they fit in kMaxSummaryBytes, the count of the rest after.
// Never longer than kMaxSummaryBytes; a short list is exactly the problems joined by "; ".
inline std::string error_summary(const std::vector<std::string>& errors) {
  // Room kept for "; ... and <20 digits> more problems".
  constexpr std::size_t kTailBytes = 48;
  std::string out;
  std::size_t shown = 0;
  for (; shown < errors.size() && shown < kMaxSummaryProblems; ++shown) {
    const std::string& e = errors[shown];
    const std::size_t size = utf8_prefix_size(e, kMaxSummaryProblemBytes);
    const std::size_t added = (shown == 0 ? 0 : 2) + size + (size < e.size() ? 3 : 0);
    const bool last = shown + 1 == errors.size();
    if (out.size() + added + (last ? 0 : kTailBytes) > kMaxSummaryBytes) break;
    if (shown > 0) out += "; ";
    out.append(e, 0, size);
    if (size < e.size()) out += "...";
  }
  const std::size_t more = errors.size() - shown;
  if (more > 0)
    out += std::string(shown == 0 ? "" : "; ") + "... and " + std::to_string(more) + " more problem" +
           (more == 1 ? "" : "s");
  return out;
}

}  // namespace lbsolid::server
