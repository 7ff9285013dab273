// lbsolid-drag-summary DIR: the drag coefficient and Reynolds number of a disk pulled through the
// fluid, from the DIR/particles.h5 that `lbsolid submit ... --out DIR` recorded (for example
// client-examples/scenarios/fig5_drag_disk.textproto). Writes DIR/summary.txt and prints it.
// Exit codes: 0 written; 2 bad input (no file, no disk in the scenario, too few frames).
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include "drag_analysis.h"
#include "lbsolid/v1/scenario.pb.h"
#include "scenario_attribute.h"
#include "io/api/scenario_translation.h"
#include "io/storage/h5md_file.h"
#include "io/version.h"
#include "summary_report.h"

namespace {

namespace fs = std::filesystem;
using namespace lbsolid;

// Written beside, then renamed: a reader of summary.txt never sees half of it.
void write_text(const fs::path& path, const std::string& text) {
  const fs::path temporary = path.string() + ".tmp";
  std::FILE* file = std::fopen(temporary.c_str(), "w");
  if (!file) throw std::runtime_error(temporary.string() + ": cannot create");
  const bool written = std::fwrite(text.data(), 1, text.size(), file) == text.size();
  if (std::fclose(file) != 0 || !written) throw std::runtime_error(temporary.string() + ": write failed");
  fs::rename(temporary, path);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "--version") {
    std::printf("lbsolid-drag-summary %s (%s)\n", LBSOLID_VERSION, LBSOLID_GIT_REVISION);
    return 0;
  }
  if (argc != 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    std::fprintf(argc == 2 ? stdout : stderr,
                 "Usage: lbsolid-drag-summary DIR\n"
                 "  reads DIR/particles.h5 (lbsolid submit SCENARIO --steps N --out DIR), fits the disk's\n"
                 "  u_x(t), writes Re, c_d and the fit to DIR/summary.txt and prints them.\n"
                 "Exit codes: 0 done; 2 bad input.\n");
    return argc == 2 ? 0 : 2;
  }
  const fs::path dir = argv[1];
  const std::string h5 = (dir / "particles.h5").string();
  try {
    if (!fs::is_regular_file(h5))
      throw std::runtime_error(h5 + ": no such file (record one with lbsolid submit SCENARIO --steps N --out DIR)");
    const std::string text = drag::read_scenario_attribute(h5);
    v1::Scenario scenario;
    std::string error;
    if (!server::parse_scenario_text(text, &scenario, &error))
      throw std::runtime_error(h5 + ": /parameters scenario: " + error);
    const drag::DragSetup setup = drag::drag_setup(scenario);
    const auto velocity = server::storage::read_h5md_series(h5, "/observables/" + setup.body + "/velocity");
    const std::string summary = drag::summary_text(setup, drag::analyse_drag(setup, velocity));
    write_text(dir / "summary.txt", summary);
    std::fputs(summary.c_str(), stdout);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lbsolid-drag-summary: %s\n", e.what());
    return 2;
  }
}
