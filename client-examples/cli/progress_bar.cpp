#include "progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lbsolid::cli {

std::string format_duration(double seconds) {
  if (!(seconds >= 0) || !std::isfinite(seconds)) return "?";
  const long long s = std::llround(seconds);
  char text[32];
  if (s < 60)
    std::snprintf(text, sizeof text, "%llds", s);
  else if (s < 3600)
    std::snprintf(text, sizeof text, "%lldm%02llds", s / 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%lldh%02lldm", s / 3600, (s % 3600) / 60);
  return text;
}

std::string format_progress_line(const ProgressSample& p) {
  const double fraction = p.target_step > 0 ? std::clamp(double(p.step) / double(p.target_step), 0.0, 1.0) : 0.0;
  char text[160];
  std::snprintf(text, sizeof text, "step %lld/%lld (%.1f%%)  %.0f steps/s  %.2f MLUPS  ETA %s", p.step, p.target_step,
                100 * fraction, p.steps_per_second, p.mlups, format_duration(p.seconds_left).c_str());
  return text;
}

std::string format_progress_bar(const ProgressSample& p, int width) {
  const double fraction = p.target_step > 0 ? std::clamp(double(p.step) / double(p.target_step), 0.0, 1.0) : 0.0;
  const int filled = static_cast<int>(fraction * width);
  std::string bar = "[";
  bar.append(filled, '#').append(width - filled, ' ').append("] ").append(format_progress_line(p));
  return bar;
}

ProgressReporter::ProgressReporter() : terminal_(isatty(STDERR_FILENO) == 1) {}

void ProgressReporter::clear_bar() {
  if (bar_drawn_) std::fputs("\r\033[K", stderr);  // carriage return, erase to end of line
  bar_drawn_ = false;
}

void ProgressReporter::progress(const ProgressSample& sample) {
  std::lock_guard lock(mutex_);
  if (terminal_) {
    clear_bar();
    std::fputs(format_progress_bar(sample, 30).c_str(), stderr);
    bar_drawn_ = true;
  } else {
    // Logs get a line every 10 s at most: a long run must not fill them with progress.
    const auto now = std::chrono::steady_clock::now();
    if (last_line_ != std::chrono::steady_clock::time_point{} && now - last_line_ < std::chrono::seconds(10)) return;
    last_line_ = now;
    std::fprintf(stderr, "%s\n", format_progress_line(sample).c_str());
  }
  std::fflush(stderr);
}

void ProgressReporter::message(const std::string& line) {
  std::lock_guard lock(mutex_);
  clear_bar();
  std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
}

void ProgressReporter::finish() {
  std::lock_guard lock(mutex_);
  if (bar_drawn_) std::fputs("\n", stderr);
  bar_drawn_ = false;
  std::fflush(stderr);
}

}  // namespace lbsolid::cli
