#pragma once
// The fuzz targets run the server's code in process: its spdlog lines, and protobuf's complaints
// about the invalid UTF-8 a fuzzer puts in string fields, would drown libFuzzer's output.
#include <google/protobuf/stubs/logging.h>
#include <spdlog/spdlog.h>

namespace lbsolid::fuzz {

inline void quiet_logging() {
  spdlog::set_level(spdlog::level::off);
  google::protobuf::SetLogHandler(nullptr);  // nullptr: log messages are discarded
}

}  // namespace lbsolid::fuzz
