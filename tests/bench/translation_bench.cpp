// lbsolid-translation-bench: how long CreateSession's validation takes for many bodies.
// translate_scenario (the API's checks and the core's validate_scene) on requests of 10^3 to 10^5
// bodies, valid and invalid, and on 40,000 chains (the 1.35 MB request that once stalled a daemon
// for 21 s). Each row: bodies, request bytes, errors found, the summary a client is sent (bytes),
// every problem joined (what the daemon sent before error_summary), and the best wall time of a
// few runs. Every case should grow as n log n or better.
//   lbsolid-translation-bench [--max-bodies N] [--case TEXT]
// (cases above N bodies are skipped, default 100000; only cases whose name holds TEXT are run)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>

#include "io/api/error_summary.h"
#include "io/api/scenario_translation.h"

namespace {

namespace v1 = lbsolid::v1;

// A D2Q7 box periodic in x between bounce-back walls, wide enough for every body to sit inside.
v1::Scenario box(int nx, int ny) {
  v1::Scenario s;
  s.set_name("translation bench");
  s.set_lattice(v1::LATTICE_D2Q7);
  s.mutable_domain()->set_nx(nx);
  s.mutable_domain()->set_ny(ny);
  s.mutable_domain()->mutable_y_low()->set_kind(v1::WALL_KIND_BOUNCE_BACK);
  s.mutable_domain()->mutable_y_high()->set_kind(v1::WALL_KIND_BOUNCE_BACK);
  return s;
}

// n bodies on a grid of cells `pitch` nodes wide; `shape` fills in each one.
v1::Scenario bodies(int n, double pitch, bool same_name, const std::function<void(v1::Body&)>& shape) {
  const int columns = 200;
  const int rows = (n + columns - 1) / columns;
  v1::Scenario s = box(static_cast<int>(columns * pitch), static_cast<int>(rows * pitch / 0.866) + 4);
  for (int b = 0; b < n; ++b) {
    v1::Body& body = *s.add_bodies();
    body.set_name(same_name ? std::string("body") : std::string("b").append(std::to_string(b)));
    shape(body);
    body.mutable_centre()->set_x((b % columns + 0.5) * pitch);
    body.mutable_centre()->set_y((b / columns + 0.5) * pitch + 1);
  }
  return s;
}

void one_label(v1::Body& body) {
  body.set_shape(v1::BODY_SHAPE_LABELS);
  body.add_labels();
}

void two_labels(v1::Body& body) {
  body.set_shape(v1::BODY_SHAPE_LABELS);
  body.add_labels();
  body.add_labels()->set_i(1);
}

// Two problems each: the translation's (a disk's radius on a labels body) and the core's (one
// label), so that every core problem is checked against as many of the translation's.
void one_label_stray_radius(v1::Body& body) {
  one_label(body);
  body.set_radius(1);
}

void chain(v1::Body& body) {
  body.set_shape(v1::BODY_SHAPE_CHAIN);
  body.set_length(8);
  body.set_axis(v1::AXIS_Y);
}

std::string only;  // --case

void run(const char* name, const v1::Scenario& scenario) {
  if (std::string(name).find(only) == std::string::npos) return;
  double best = 1e300;
  std::size_t errors = 0, summary = 0, joined = 0;
  for (int repeat = 0; repeat < 3; ++repeat) {
    const auto start = std::chrono::steady_clock::now();
    const auto t = lbsolid::server::translate_scenario(scenario);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    best = std::min(best, seconds);
    errors = t.errors.size();
    summary = lbsolid::server::error_summary(t.errors).size();
    joined = 0;
    for (const auto& e : t.errors) joined += e.size() + (joined == 0 ? 0 : 2);
    if (seconds > 5) break;  // one run of a slow case is enough
  }
  std::printf("%-30s %8d %10zu %8zu %8zu %10zu %10.4f\n", name, scenario.bodies_size(), scenario.ByteSizeLong(),
              errors, summary, joined, best);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  long max_bodies = 100000;
  for (int a = 1; a < argc; ++a) {
    if (std::strcmp(argv[a], "--max-bodies") == 0 && a + 1 < argc) {
      max_bodies = std::strtol(argv[++a], nullptr, 10);
    } else if (std::strcmp(argv[a], "--case") == 0 && a + 1 < argc) {
      only = argv[++a];
    } else {
      std::fprintf(stderr, "usage: %s [--max-bodies N] [--case TEXT]\n", argv[0]);
      return 2;
    }
  }
  std::printf("%-30s %8s %10s %8s %8s %10s %10s\n", "case", "bodies", "bytes", "errors", "summary", "joined",
              "seconds");
  for (int n : {1000, 10000, 100000}) {
    if (n > max_bodies) continue;
    char name[64];
    const auto named = [&](const char* what) {
      std::snprintf(name, sizeof name, "%s %d", what, n);
      return name;
    };
    run(named("one-label, unique names"), bodies(n, 4, false, one_label));
    run(named("one-label, one name"), bodies(n, 4, true, one_label));
    run(named("two-label (valid)"), bodies(n, 4, false, two_labels));
    run(named("two-label, one name"), bodies(n, 4, true, two_labels));
    run(named("one-label + radius"), bodies(n, 4, false, one_label_stray_radius));
  }
  if (40000 <= max_bodies) {
    run("chains (valid) 40000", bodies(40000, 10, false, chain));
    run("chains, one name 40000", bodies(40000, 10, true, chain));
    // Default names ("body<b>"), as a client that names nothing sends them.
    v1::Scenario unnamed = bodies(40000, 10, false, chain);
    for (auto& body : *unnamed.mutable_bodies()) body.clear_name();
    run("chains, unnamed (valid) 40000", unnamed);
  }
  return 0;
}
