// The lbsolid CLI against a real daemon: its exit codes (0 done, 1 the run failed, 2 bad input,
// 3 daemon unreachable), its --json output, and the files `submit --out` leaves behind.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "service/daemon_process.h"

namespace lbsolid::testing {
namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code;
  std::string out;
};

// Runs the CLI with `args`, capturing stdout (stderr goes to the test log).
Result cli(const std::string& args) {
  const std::string command = std::string(LBSOLID_CLI_PATH) + " " + args;
  FILE* pipe = popen(command.c_str(), "r");
  std::string out;
  char buffer[4096];
  while (std::size_t n = fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

std::string write_file(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

const char* kSmallScenario = R"(
name: "cli test"
domain { nx: 24 ny: 12 y_low { kind: WALL_KIND_BOUNCE_BACK } y_high { kind: WALL_KIND_BOUNCE_BACK } }
fluid { omega: 1.2 body_force { x: 1e-5 } }
bodies { name: "disk" shape: BODY_SHAPE_DISK radius: 2 centre { x: 8 y: 6 } load { x: 1e-5 } }
)";

class Cli : public ::testing::Test {
 protected:
  Cli() : scoped_("lbsolid-cli"), dir_(scoped_.path), daemon_(dir_ + "/data") {}
  std::string server() const { return "--server " + daemon_.address() + " "; }
  ScopedDirectory scoped_;  // declared first: removed after the daemon has exited
  const std::string& dir_;
  DaemonProcess daemon_;
};

TEST_F(Cli, SubmitAndWaitExitsZeroAndWritesResults) {
  const auto scenario = write_file(dir_, "small.textproto", kSmallScenario);
  const auto out = dir_ + "/out";
  const auto r = cli(server() + "--json submit " + scenario + " --steps 60 --out " + out);
  EXPECT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("\"DONE\""), std::string::npos) << r.out;
  for (const char* file : {"status.json", "particles.h5", "fields.h5", "fields.xdmf"})
    EXPECT_TRUE(fs::exists(out + "/" + file)) << file;
  std::stringstream status;
  status << std::ifstream(out + "/status.json").rdbuf();
  EXPECT_NE(status.str().find("\"state\":\"DONE\""), std::string::npos) << status.str();
  EXPECT_NE(status.str().find("\"step\":60"), std::string::npos) << status.str();
  EXPECT_NE(status.str().find("\"checksum\":\""), std::string::npos) << status.str();
}

TEST_F(Cli, BadInputExitsTwo) {
  const auto broken = write_file(dir_, "broken.textproto", "domain { nx: 10 ny: }\n");
  EXPECT_EQ(cli(server() + "submit " + broken + " --steps 5").exit_code, 2);
  std::string wrong_omega = kSmallScenario;
  wrong_omega.replace(wrong_omega.find("omega: 1.2"), 10, "omega: 2.5");
  const auto refused = write_file(dir_, "omega.textproto", wrong_omega);
  const auto r = cli(server() + "--json submit " + refused + " --steps 5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("scenario.fluid.omega"), std::string::npos) << r.out;
  EXPECT_EQ(cli(server() + "status s-999999").exit_code, 2);  // NOT_FOUND
  EXPECT_EQ(cli(server() + "no-such-command").exit_code, 2);
}

TEST_F(Cli, FailedRunExitsOne) {
  // A body force that drives the flow past the Mach limit within the first check.
  const auto diverging = write_file(dir_, "diverging.textproto", R"(
domain { nx: 8 ny: 8 }
fluid { body_force { x: 0.01 } }
stability { check_interval: 10 max_mach: 0.3 }
)");
  const auto r = cli(server() + "--json submit " + diverging + " --steps 1000 --wait");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("Mach number"), std::string::npos) << r.out;
}

TEST_F(Cli, UnreachableDaemonExitsThree) {
  EXPECT_EQ(cli("--server 127.0.0.1:1 --timeout 2 info").exit_code, 3);
}

}  // namespace
}  // namespace lbsolid::testing
