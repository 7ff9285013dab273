#pragma once
// The run length a scenario file declares for itself: its first comment line "# steps: N ..."
// (every example scenario has one, with why N), so that `submit FILE` needs no --steps for it.
#include <istream>
#include <string>

namespace lbsolid::cli {

// N from the first line "# steps: N" (spaces around the words optional, anything after N a
// comment), 0 when no line declares it. A declaring line whose N is not a positive integer is a
// UsageError naming the file's line, as a bad --steps would be.
long declared_steps(std::istream& text, const std::string& name);
// The same for a file; 0 also when it cannot be read (loading it reports that).
long declared_steps(const std::string& path);

}  // namespace lbsolid::cli
