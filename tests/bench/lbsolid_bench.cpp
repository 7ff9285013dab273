// lbsolid-bench: fluid kernel throughput against the memory roofline.
// For each lattice, precision and streaming scheme: MLUPS on a grid far larger than the last-level
// cache, with one thread and with all cores, beside the memory bandwidth measured in the same run
// (a STREAM-style copy for two-buffer streaming, an in-place update for in-place streaming), the
// bytes moved per cell update, the roofline that implies, and the fraction of it reached.
// Then the collision operators (BGK, TRT, regularized) side by side: D2Q9 and D3Q19, double, in
// place, one thread, on the same grid.
// Then the scene benchmarks (bench/scene_bench.h): the builder's overhead on a fluid-only scene,
// a solid-only scene's memory, and coupled steps at 0.1 and 1 particle per cell, with one thread
// and, with --threads N, with N fluid threads too (and the speed-up).
//   lbsolid-bench [--json] [--quick] [--threads N] [--scenes-only | --kernels-only]
// (--kernels-only: the fluid kernels alone, e.g. to hold a portable build against a native one:
// tests/bench/portable_vs_native.sh)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "bench/memory_bandwidth.h"
#include "bench/scene_bench.h"
#include "fluid/fluid_lattice.h"
#include "fluid/kernel_isa.h"
#include "lattice/d2q7.h"
#include "lattice/d2q9.h"
#include "lattice/d3q19.h"

namespace lbsolid::bench {
namespace {

struct Row {
  std::string lattice, precision, streaming, collision = "bgk";
  std::string layout;  // how the populations are stored (FluidLattice::chosen_layout)
  int threads;
  long cells;
  double mlups, bytes_per_update, bandwidth, roofline;
};

// Grid with at least `min_cells` cells: square in 2D, cubic in 3D, with sides a multiple of 16
// cells (a whole number of vectors of any width, as a user who wants speed chooses them: the
// in-place pulling step's shifted sweep needs it; docs/performance.md has other sizes too).
template <class L>
fluid::FluidConfig big_grid(long min_cells, int threads, fluid::StreamingScheme streaming,
                            fluid::CollisionModel collision) {
  fluid::FluidConfig c;
  auto whole_vectors = [](double side) { return (static_cast<int>(std::ceil(side)) + 15) / 16 * 16; };
  if (L::D == 3) {
    const int n = whole_vectors(std::cbrt(static_cast<double>(min_cells)));
    c.nx = c.ny = c.nz = n;
  } else {
    const int n = whole_vectors(std::sqrt(static_cast<double>(min_cells)));  // even: D2Q7 periodic in y needs it
    c.nx = c.ny = n;
  }
  c.omega = 1.0;
  c.threads = threads;
  c.streaming = streaming;
  c.collision = collision;
  return c;
}

// Bytes per cell update are counted as STREAM counts a copy: Q populations read and Q written,
// whichever the scheme (in place, the written lines are the ones just read).
template <class L, class T>
Row measure(std::size_t working_set, int threads, fluid::StreamingScheme streaming, double min_seconds,
            fluid::CollisionModel collision = fluid::CollisionModel::kBgk) {
  const double bytes_per_update = 2.0 * L::Q * sizeof(T);
  // Each scheme's own storage (one buffer or two) fills the working set.
  const int buffers = streaming == fluid::StreamingScheme::kInPlace ? 1 : 2;
  const long cells = static_cast<long>(working_set / (buffers * L::Q * sizeof(T)));
  fluid::FluidLattice<L, T> fluid(big_grid<L>(cells, threads, streaming, collision));
  fluid.initialize([](int, int, int) { return 1.0; },
                   [](int x, int y, int) { return fluid::Vec3{0.01 * std::sin(0.1 * y), 0.01 * std::cos(0.1 * x), 0}; });
  fluid.run(2);  // warm up: page in both buffers
  // Best of several timed segments, as STREAM reports its best copy: on a shared machine the
  // best segment is the one least disturbed by other work.
  constexpr int kSegments = 5;
  double mlups = 0;
  for (int segment = 0; segment < kSegments; ++segment) {
    long steps = 0;
    double seconds = 0;
    const auto start = std::chrono::steady_clock::now();
    while (seconds < min_seconds / kSegments) {
      fluid.step();
      ++steps;
      seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    mlups = std::max(mlups, static_cast<double>(fluid.cells()) * steps / seconds / 1e6);
  }
  return {L::name, sizeof(T) == 8 ? "double" : "float",
          streaming == fluid::StreamingScheme::kInPlace ? "in-place" : "two-buffer",
          fluid::collision_model_name(collision), fluid.layout() == fluid::PopulationLayout::kBlocks ? "blocks" : "arrays",
          threads, fluid.cells(), mlups, bytes_per_update, 0, 0};  // bandwidth and roofline: filled in by the caller
}

}  // namespace
}  // namespace lbsolid::bench

int main(int argc, char** argv) {
  using namespace lbsolid;
  using namespace lbsolid::bench;
  bool json = false, quick = false, scenes_only = false, kernels_only = false;
  int all = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  for (int k = 1; k < argc; ++k) {
    if (!std::strcmp(argv[k], "--json")) json = true;
    else if (!std::strcmp(argv[k], "--quick")) quick = true;
    else if (!std::strcmp(argv[k], "--scenes-only")) scenes_only = true;
    else if (!std::strcmp(argv[k], "--kernels-only")) kernels_only = true;
    else if (!std::strcmp(argv[k], "--threads") && k + 1 < argc) all = std::max(1, std::atoi(argv[++k]));
    else {
      std::fprintf(stderr, "usage: lbsolid-bench [--json] [--quick] [--threads N] [--scenes-only | --kernels-only]\n");
      return 2;
    }
  }
  if (scenes_only && kernels_only) {
    std::fprintf(stderr, "lbsolid-bench: --scenes-only and --kernels-only leave nothing to run\n");
    return 2;
  }
  if (const std::string error = fluid::kernel_isa_environment_error(); !error.empty()) {
    std::fprintf(stderr, "lbsolid-bench: %s\n", error.c_str());
    return 2;
  }
  const std::size_t llc = last_level_cache_bytes();
  // Working sets of 8x the last-level cache (quick: 4x) leave no doubt the cache cannot hold them.
  const std::size_t working_set = (quick ? 4 : 8) * llc;
  const double min_seconds = quick ? 0.5 : 3.0;
  std::vector<int> thread_counts = {1};
  if (all > 1) thread_counts.push_back(all);

  std::vector<Row> rows;
  for (int threads : scenes_only ? std::vector<int>{} : thread_counts) {
    for (auto scheme : {fluid::StreamingScheme::kInPlace, fluid::StreamingScheme::kTwoBuffer}) {
      // Each scheme is held against the STREAM-style loop with its access pattern: in place
      // against an update of one array, two buffers against a copy between two.
      const int repeats = quick ? 4 : 10;
      auto bandwidth_now = [&] {
        return scheme == fluid::StreamingScheme::kInPlace ? update_bandwidth(working_set, threads, repeats)
                                                          : copy_bandwidth(working_set / 2, threads, repeats);
      };
      // The bandwidth is the best seen in measurements interleaved with the kernels: on a shared
      // machine a single measurement may be disturbed, and a low one would flatter the kernels.
      double bandwidth = 0;
      const std::size_t first = rows.size();
      auto add = [&](Row row) {
        rows.push_back(row);
        bandwidth = std::max(bandwidth, bandwidth_now());
      };
      bandwidth = bandwidth_now();
      add(measure<lattice::D2Q9, double>(working_set, threads, scheme, min_seconds));
      add(measure<lattice::D2Q9, float>(working_set, threads, scheme, min_seconds));
      add(measure<lattice::D2Q7, double>(working_set, threads, scheme, min_seconds));
      add(measure<lattice::D2Q7, float>(working_set, threads, scheme, min_seconds));
      add(measure<lattice::D3Q19, double>(working_set, threads, scheme, min_seconds));
      add(measure<lattice::D3Q19, float>(working_set, threads, scheme, min_seconds));
      for (std::size_t k = first; k < rows.size(); ++k) {
        rows[k].bandwidth = bandwidth;
        rows[k].roofline = bandwidth / rows[k].bytes_per_update / 1e6;
      }
    }
  }

  // The operators against each other, where the arithmetic differs most (D3Q19) and least (D2Q9).
  std::vector<Row> collision_rows;
  if (!scenes_only && !kernels_only) {
    constexpr auto kInPlace = fluid::StreamingScheme::kInPlace;
    for (auto model : {fluid::CollisionModel::kBgk, fluid::CollisionModel::kTrt, fluid::CollisionModel::kRegularized}) {
      collision_rows.push_back(measure<lattice::D2Q9, double>(working_set, 1, kInPlace, min_seconds, model));
      collision_rows.push_back(measure<lattice::D3Q19, double>(working_set, 1, kInPlace, min_seconds, model));
    }
  }

  std::vector<SceneRow> scene_rows;
  for (int threads : kernels_only ? std::vector<int>{} : thread_counts)
    for (SceneRow& row : run_scene_benchmarks(quick, threads)) scene_rows.push_back(std::move(row));
  if (json) {
    std::printf("{\n  \"kernel_isa\": \"%s\",\n  \"last_level_cache_bytes\": %zu,\n  \"working_set_bytes\": %zu,\n  \"results\": [\n",
                fluid::kernel_isa_name(fluid::kernel_isa()), llc, working_set);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const Row& r = rows[k];
      std::printf("    {\"lattice\": \"%s\", \"precision\": \"%s\", \"streaming\": \"%s\", \"layout\": \"%s\", "
                  "\"threads\": %d, \"cells\": %ld, "
                  "\"mlups\": %.2f, \"bytes_per_update\": %.0f, \"stream_bandwidth_gbs\": %.2f, "
                  "\"roofline_mlups\": %.2f, \"fraction_of_roofline\": %.3f}%s\n",
                  r.lattice.c_str(), r.precision.c_str(), r.streaming.c_str(), r.layout.c_str(), r.threads, r.cells, r.mlups,
                  r.bytes_per_update,
                  r.bandwidth / 1e9, r.roofline, r.mlups / r.roofline, k + 1 < rows.size() ? "," : "");
    }
    std::printf("  ],\n  \"collision_results\": [\n");
    for (std::size_t k = 0; k < collision_rows.size(); ++k) {
      const Row& r = collision_rows[k];
      std::printf("    {\"lattice\": \"%s\", \"precision\": \"%s\", \"streaming\": \"%s\", \"collision\": \"%s\", "
                  "\"threads\": %d, \"cells\": %ld, \"mlups\": %.2f}%s\n",
                  r.lattice.c_str(), r.precision.c_str(), r.streaming.c_str(), r.collision.c_str(), r.threads, r.cells,
                  r.mlups, k + 1 < collision_rows.size() ? "," : "");
    }
    std::printf("  ],\n");
    print_scene_rows_json(scene_rows);
    std::printf("}\n");
    return 0;
  }
  if (scenes_only) {
    print_scene_rows(scene_rows);
    return 0;
  }
  std::printf("lbsolid-bench: fused BGK stream-collide, periodic box, in-place (AA) and two-buffer streaming\n");
  std::printf("last-level cache %.0f MiB; working set %.0f MiB per run; kernels for %s\n\n", llc / 1048576.0,
              working_set / 1048576.0, fluid::kernel_isa_name(fluid::kernel_isa()));
  std::printf("%-6s %-7s %-10s %-6s %7s %10s %9s %11s %12s %14s %9s\n", "lattice", "prec", "streaming", "layout", "threads",
              "cells", "MLUPS", "bytes/cell", "stream GB/s", "roofline MLUPS", "fraction");
  for (const Row& r : rows) {
    std::printf("%-6s %-7s %-10s %-6s %7d %10ld %9.1f %11.0f %12.1f %14.1f %8.0f%%\n", r.lattice.c_str(),
                r.precision.c_str(), r.streaming.c_str(), r.layout.c_str(), r.threads, r.cells, r.mlups, r.bytes_per_update,
                r.bandwidth / 1e9,
                r.roofline, 100.0 * r.mlups / r.roofline);
  }
  for (const Row& r : rows) {
    if (r.mlups > r.roofline) {
      std::printf("\nnote: a fraction above 100%% means every bandwidth measurement of that group was\n"
                  "disturbed by other work on the machine; run again on a quiet machine.\n");
      break;
    }
  }
  if (kernels_only) return 0;
  std::printf("\ncollision operators (in place, one thread; MLUPS relative to BGK on the same lattice)\n");
  std::printf("%-6s %-7s %-12s %10s %9s %8s\n", "lattice", "prec", "collision", "cells", "MLUPS", "vs BGK");
  for (const Row& r : collision_rows) {
    double bgk = 0;
    for (const Row& b : collision_rows)
      if (b.lattice == r.lattice && b.collision == "bgk") bgk = b.mlups;
    std::printf("%-6s %-7s %-12s %10ld %9.1f %7.0f%%\n", r.lattice.c_str(), r.precision.c_str(), r.collision.c_str(),
                r.cells, r.mlups, bgk > 0 ? 100.0 * r.mlups / bgk : 0.0);
  }
  print_scene_rows(scene_rows);
  return 0;
}
