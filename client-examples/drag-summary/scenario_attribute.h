#pragma once
// The scenario an H5MD file was recorded from: the string attribute "scenario" of /parameters.
// The storage library's reader returns time series only, so this reads the attribute with the
// HDF5 C API, accepting fixed-length (as lbsolid writes it) and variable-length strings.
#include <string>

namespace lbsolid::drag {

// Throws std::runtime_error naming the path and the cause.
std::string read_scenario_attribute(const std::string& h5_path);

}  // namespace lbsolid::drag
