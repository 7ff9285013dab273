#pragma once
// SHA-256 as coreutils' sha256sum computes it: a hash of test data that the code under test did
// not compute (tokens files, downloaded outputs).
#include <cstdlib>
#include <fstream>
#include <string>

#include "service/daemon_process.h"

namespace lbsolid::testing {

// Lowercase hex; empty if sha256sum could not run.
inline std::string coreutils_sha256(const std::string& bytes) {
  const ScopedDirectory dir("lbsolid-sha");
  { std::ofstream(dir.path + "/in", std::ios::binary) << bytes; }
  const std::string command = "sha256sum '" + dir.path + "/in' > '" + dir.path + "/out'";
  if (std::system(command.c_str()) != 0) return "";
  std::ifstream in(dir.path + "/out");
  std::string hash;
  in >> hash;
  return hash;
}

}  // namespace lbsolid::testing
