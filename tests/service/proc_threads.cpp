#include "service/proc_threads.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

namespace lbsolid::testing {

namespace {

// The fields of a stat file from 3 (state) to 19 (nice), indexed by field number; empty if the
// file is gone.
std::vector<std::string> stat_fields(const std::filesystem::path& file) {
  std::ifstream in(file);
  const std::string stat((std::istreambuf_iterator<char>(in)), {});
  const auto after_name = stat.rfind(')');  // the name may hold spaces and parentheses
  if (after_name == std::string::npos) return {};
  std::istringstream text(stat.substr(after_name + 2));
  std::vector<std::string> field(20);
  for (int i = 3; i <= 19; ++i)
    if (!(text >> field[i])) return {};
  return field;
}

double cpu_seconds(const std::vector<std::string>& field) {  // utime + stime, fields 14 and 15
  return (std::stod(field[14]) + std::stod(field[15])) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

}  // namespace

std::vector<ThreadStat> thread_stats(int pid) {
  std::vector<ThreadStat> threads;
  std::error_code error;
  for (const auto& task : std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/task", error)) {
    const auto field = stat_fields(task.path() / "stat");
    if (!field.empty()) threads.push_back({std::stoi(task.path().filename().string()), std::stoi(field[19]), cpu_seconds(field)});
  }
  return threads;
}

double process_cpu_seconds(int pid) {
  const auto field = stat_fields("/proc/" + std::to_string(pid) + "/stat");
  return field.empty() ? 0 : cpu_seconds(field);
}

}  // namespace lbsolid::testing
