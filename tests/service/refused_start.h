#pragma once
// A daemon started with flags it must refuse: it exits at start with status 2 and its log names
// the reason.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "service/daemon_process.h"
#include "service/test_certificates.h"

namespace lbsolid::testing {

inline void expect_refused_start(const std::vector<std::string>& flags, const std::string& fragment) {
  const ScopedDirectory dir("lbsolid-refused");
  const std::string log = dir.path + "/log";
  try {
    DaemonProcess daemon(dir.path + "/data", flags, {}, {nullptr, log});
    ADD_FAILURE() << "started with the flags that must be refused";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("exited at start with status 2"), std::string::npos) << e.what();
  }
  EXPECT_NE(file_text(log).find(fragment), std::string::npos) << file_text(log);
}

}  // namespace lbsolid::testing
