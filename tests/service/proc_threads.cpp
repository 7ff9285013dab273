#include "service/proc_threads.h"

#include <fcntl.h>
#include <unistd.h>

#include <filesystem>
#include <sstream>
#include <string>

namespace lbsolid::testing {

namespace {

// The whole of a /proc file, or "" if it cannot be read. Not through std::ifstream: a thread that
// ends between the open and the read makes read() fail with ESRCH, and libstdc++'s filebuf
// throws on that (ios_base::failure "No such process"), which is an ordinary event here.
std::string read_proc_file(const std::filesystem::path& file) {
  const int fd = open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return {};
  std::string text;
  char buffer[1024];
  ssize_t got = 0;
  while ((got = read(fd, buffer, sizeof buffer)) > 0) text.append(buffer, static_cast<std::size_t>(got));
  close(fd);
  return got < 0 ? std::string() : text;
}

// The fields of a stat file from 3 (state) to 19 (nice), indexed by field number; empty if the
// file is gone.
std::vector<std::string> stat_fields(const std::filesystem::path& file) {
  const std::string stat = read_proc_file(file);
  const auto after_name = stat.rfind(')');  // the name may hold spaces and parentheses
  if (after_name == std::string::npos || after_name + 2 > stat.size()) return {};
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
  // increment(error), not ++: a listing that fails part-way ends it rather than throwing.
  for (std::filesystem::directory_iterator task("/proc/" + std::to_string(pid) + "/task", error), end;
       !error && task != end; task.increment(error)) {
    const auto field = stat_fields(task->path() / "stat");
    if (!field.empty()) threads.push_back({std::stoi(task->path().filename().string()), std::stoi(field[19]), cpu_seconds(field)});
  }
  return threads;
}

double process_cpu_seconds(int pid) {
  const auto field = stat_fields("/proc/" + std::to_string(pid) + "/stat");
  return field.empty() ? 0 : cpu_seconds(field);
}

}  // namespace lbsolid::testing
