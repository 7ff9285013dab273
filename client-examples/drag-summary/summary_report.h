#pragma once
// The text of summary.txt (also printed): the scenario, u(t) as a table of about 40 rows, the
// fit, Re, c_d, c_d Re, and what the paper leads one to expect.
#include <string>

#include "drag_analysis.h"

namespace lbsolid::drag {

std::string summary_text(const DragSetup& setup, const DragResult& result);

}  // namespace lbsolid::drag
