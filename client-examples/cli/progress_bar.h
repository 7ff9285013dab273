#pragma once
// Progress of a followed run on stderr: a bar redrawn in place when stderr is a terminal, plain
// lines (at most one per 10 s, plus every state change) when it is a log or a pipe. Thread-safe:
// the event stream and the status poll both report.
#include <chrono>
#include <mutex>
#include <string>

namespace lbsolid::cli {

struct ProgressSample {
  long long step = 0, target_step = 0;
  double steps_per_second = 0, mlups = 0;
  double seconds_left = -1;  // < 0: unknown
};

// Pure formatting, unit-tested.
std::string format_duration(double seconds);  // "42s", "3m07s", "2h05m"; "?" if negative
std::string format_progress_line(const ProgressSample& p);            // "step 1200/15000 (8.0%)  ..."
std::string format_progress_bar(const ProgressSample& p, int width);  // "[#####     ] " + line

class ProgressReporter {
 public:
  ProgressReporter();  // draws a bar if stderr is a terminal
  ~ProgressReporter() { finish(); }
  void progress(const ProgressSample& sample);
  void message(const std::string& line);  // a state change or an error: always printed
  void finish();                          // ends the bar's line

 private:
  void clear_bar();  // with the mutex held
  std::mutex mutex_;
  bool terminal_ = false;
  bool bar_drawn_ = false;
  std::chrono::steady_clock::time_point last_line_{};
};

}  // namespace lbsolid::cli
