// HDF5 storage: checkpoints continue a run bit for bit through a file and are replaced atomically;
// field snapshots hold [z][y][x] data with an XDMF index ParaView reads; H5MD files have the H5MD
// 1.1 structure, read back exactly, and appear under their final name only when closed.
#include <fcntl.h>
#include <grp.h>
#include <gtest/gtest.h>
#include <linux/capability.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <latch>
#include <map>
#include <mutex>
#include <regex>
#include <thread>

#include "scene/restart_support.h"
#include "scene/simulation.h"
#include "io/storage/checkpoint_file.h"
#include "io/storage/checkpoint_layout.h"
#include "io/storage/field_snapshot.h"
#include "io/storage/file_replace.h"
#include "io/storage/h5md_file.h"
#include "io/storage/hdf5_io.h"

namespace lbsolid::server::storage {
namespace {

namespace fs = std::filesystem;
using scene::LatticeKind;
using scene::testing::coupled_scene;
using scene::testing::expect_same_state;
using scene::testing::same_bytes;
using scene::Precision;

// A fresh directory under the system temporary directory, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    const auto now = std::chrono::steady_clock::now().time_since_epoch().count();
    path_ = fs::temp_directory_path() /
            ("lbsolid-storage-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" +
             std::to_string(now));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(path_)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  fs::path path_;
};

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

template <class F>
std::string thrown_message(F&& action) {
  try {
    action();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

CheckpointContents contents_of(const scene::Simulation& simulation) {
  CheckpointContents contents;
  contents.scenario_text = "fluid {\n  nx: 16\n  omega: 1.3\n}\nname: \"disk \\\"one\\\"\"\n\n";
  contents.session_id = "7f3c9a2e-session";
  contents.session_name = "sédimentation test";
  contents.target_step = 1000;
  contents.state = simulation.save_state();
  return contents;
}

const WriterInfo kWriter{"0.1.0", "abc1234"};

// --- checkpoints ------------------------------------------------------------------------------

// N steps, checkpoint file, N more steps in a new simulation == 2N straight steps, bit for bit.
void expect_restart_through_file_is_exact(const scene::Scene& scene) {
  TempDir dir;
  const std::string path = dir.file("session.h5");
  constexpr long n = 25;  // odd: the in-place scheme is saved mid-pair
  auto straight = scene::build_simulation(scene);
  straight->run(2 * n);

  auto first = scene::build_simulation(scene);
  first->run(n);
  const CheckpointContents written = contents_of(*first);
  write_checkpoint(path, written, kWriter);
  const CheckpointContents read = read_checkpoint(path);
  EXPECT_EQ(read.scenario_text, written.scenario_text);
  EXPECT_EQ(read.session_id, written.session_id);
  EXPECT_EQ(read.session_name, written.session_name);
  EXPECT_EQ(read.target_step, written.target_step);
  expect_same_state(read.state, written.state);

  auto second = scene::build_simulation(scene);
  second->load_state(read.state);
  EXPECT_EQ(second->step_count(), n);
  second->run(n);
  expect_same_state(second->save_state(), straight->save_state());
}

TEST(CheckpointFile, CoupledRunContinuesBitForBitInDouble) {
  expect_restart_through_file_is_exact(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
}

TEST(CheckpointFile, CoupledRunContinuesBitForBitInFloat) {
  expect_restart_through_file_is_exact(coupled_scene(LatticeKind::kD2Q9, Precision::kFloat));
}

TEST(CheckpointFile, CoupledThreeDimensionalTwoBufferRunContinuesBitForBit) {
  scene::Scene s = coupled_scene(LatticeKind::kD3Q19, Precision::kFloat);
  s.fluid.streaming = fluid::StreamingScheme::kTwoBuffer;
  expect_restart_through_file_is_exact(s);
}

TEST(CheckpointFile, SolidOnlyRunContinuesBitForBit) {
  scene::Scene s = coupled_scene(LatticeKind::kD2Q9, Precision::kDouble);
  s.with_fluid = false;
  s.fluid.body_force = {0, 0, 0};
  expect_restart_through_file_is_exact(s);
  TempDir dir;
  auto simulation = scene::build_simulation(s);
  write_checkpoint(dir.file("c.h5"), contents_of(*simulation), kWriter);
  const CheckpointContents read = read_checkpoint(dir.file("c.h5"));
  EXPECT_FALSE(read.state.has_fluid);
  EXPECT_TRUE(read.state.has_solid);
}

// A chain torn by its loads: links break and particles are shed before the checkpoint (step 25);
// the broken links and the shed momentum go through the file exactly, and the pieces move on as
// they would have (a crack's links breaking across a restore: tests/physics/fracture_test.cpp).
TEST(CheckpointFile, BrokenLinksAndShedParticlesContinueBitForBit) {
  scene::Scene s;
  s.with_fluid = false;
  s.fluid.nx = s.fluid.ny = 128;
  s.contact.enabled = false;
  solid::BodySpec chain;
  chain.shape = solid::BodyShape::kChain;
  chain.length = 16;
  chain.centre = {64, 64, 0};
  chain.velocity = {0.003, -0.001, 0};
  chain.load = {2e-4, 1e-4, 0};
  chain.point_loads = {{{0, 0, 0}, {-1.5e-3, 0.7e-3, 0}}, {{15, 0, 0}, {1.2e-3, 0, 0}}};
  chain.fracture.max_force = 1e-3;
  s.bodies.push_back(chain);
  expect_restart_through_file_is_exact(s);
  auto simulation = scene::build_simulation(s);
  simulation->run(25);
  const auto state = simulation->save_state();
  ASSERT_GE(state.solid.broken.size(), 2u) << "the test needs breaks before the checkpoint";
  ASSERT_FALSE(state.solid.shed_momentum.empty()) << "and a shed particle";
}

TEST(CheckpointFile, RootAttributesDescribeTheWriter) {
  TempDir dir;
  auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
  write_checkpoint(dir.file("c.h5"), contents_of(*simulation), kWriter);
  h5::File file(H5Fopen(dir.file("c.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  ASSERT_TRUE(file.valid());
  EXPECT_EQ(h5::read_string_attribute(file.get(), "format"), "lbsolid-checkpoint");
  EXPECT_EQ(h5::read_attribute<int>(file.get(), "format_version"), kCheckpointFormatVersion);
  EXPECT_EQ(h5::read_string_attribute(file.get(), "lbsolid_version"), "0.1.0");
  EXPECT_EQ(h5::read_string_attribute(file.get(), "git_revision"), "abc1234");
  const auto positions = h5::read_dataset<double>(file.get(), "solid/positions");
  EXPECT_EQ(positions.dims, (std::vector<hsize_t>{simulation->save_state().solid.positions.size(), 3}));
}

TEST(CheckpointFile, EmptyAndUnusualStringsRoundTrip) {
  TempDir dir;
  auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
  CheckpointContents contents = contents_of(*simulation);
  contents.session_name = "";
  contents.scenario_text = std::string("line\n\ttab\r\nnul:") + '\0' + "end\n";
  write_checkpoint(dir.file("c.h5"), contents, {"", ""});
  const CheckpointContents read = read_checkpoint(dir.file("c.h5"));
  EXPECT_EQ(read.session_name, "");
  EXPECT_EQ(read.scenario_text, contents.scenario_text);
}

TEST(CheckpointFile, LeavesNoTemporaryFileBehind) {
  TempDir dir;
  auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
  write_checkpoint(dir.file("c.h5"), contents_of(*simulation), kWriter);
  simulation->run(3);
  write_checkpoint(dir.file("c.h5"), contents_of(*simulation), kWriter);  // replaces the first
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"c.h5"});
  EXPECT_EQ(read_checkpoint(dir.file("c.h5")).state.step, 3);
}

// Runs write(i) for i < writers on as many threads, released together; returns the first failure
// ("" when every write succeeded).
template <class Write>
std::string write_all_at_once(int writers, Write write) {
  std::latch start(writers);
  std::string first_failure;
  std::mutex failure_mutex;
  std::vector<std::thread> threads;
  for (int i = 0; i < writers; ++i)
    threads.emplace_back([&, i] {
      start.arrive_and_wait();
      try {
        write(i);
      } catch (const std::exception& e) {
        std::lock_guard lock(failure_mutex);
        if (first_failure.empty()) first_failure = e.what();
      }
    });
  for (auto& t : threads) t.join();
  return first_failure;
}

// Simultaneous writes of one target (the daemon's concurrent Checkpoint calls) each use their own
// temporary file: all succeed, the target is exactly one writer's content, and nothing is left.
TEST(CheckpointFile, ConcurrentWritesOfOneTargetLeaveOneCompleteCheckpoint) {
  TempDir dir;
  const std::string path = dir.file("c.h5");
  constexpr int kWriters = 8;
  auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
  std::vector<CheckpointContents> versions;
  for (int i = 0; i < kWriters; ++i) {
    versions.push_back(contents_of(*simulation));
    versions.back().session_name = "writer " + std::to_string(i);
    simulation->run(1);
  }
  for (int round = 0; round < 5; ++round) {
    ASSERT_EQ(write_all_at_once(kWriters, [&](int i) { write_checkpoint(path, versions[i], kWriter); }), "")
        << "round " << round;
    const CheckpointContents read = read_checkpoint(path);
    const long i = read.state.step;
    ASSERT_TRUE(i >= 0 && i < kWriters) << read.state.step;
    EXPECT_EQ(read.session_name, versions[i].session_name);
    expect_same_state(read.state, versions[i].state);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"c.h5"});
  }
}

TEST(TextFileReplacing, ConcurrentWritesOfOneTargetLeaveOneCompleteFile) {
  TempDir dir;
  const std::string path = dir.file("index.xdmf");
  constexpr int kWriters = 8;
  std::vector<std::string> texts;
  for (int i = 0; i < kWriters; ++i) texts.push_back(std::string(200000 + 1000 * i, static_cast<char>('a' + i)));
  for (int round = 0; round < 10; ++round) {
    ASSERT_EQ(write_all_at_once(kWriters, [&](int i) { write_text_file_replacing(path, texts[i]); }), "")
        << "round " << round;
    const std::string read = file_bytes(path);
    EXPECT_TRUE(std::find(texts.begin(), texts.end(), read) != texts.end())
        << "round " << round << ": " << read.size() << " bytes that no writer wrote alone";
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"index.xdmf"});
  }
}

TEST(CheckpointFile, IdenticalContentGivesIdenticalFiles) {
  TempDir dir;
  auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
  write_checkpoint(dir.file("a.h5"), contents_of(*simulation), kWriter);
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // a time stamp would now differ
  write_checkpoint(dir.file("b.h5"), contents_of(*simulation), kWriter);
  EXPECT_TRUE(file_bytes(dir.file("a.h5")) == file_bytes(dir.file("b.h5")));
}

TEST(CheckpointFile, MissingDirectoryIsReportedWithThePath) {
  TempDir dir;
  auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
  const std::string path = dir.file("no/such/dir/c.h5");
  const std::string message = thrown_message([&] { write_checkpoint(path, contents_of(*simulation), kWriter); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{});
}

TEST(CheckpointFile, DirectoryThatIsAFileIsReportedWithThePath) {
  TempDir dir;
  std::ofstream(dir.file("plain")) << "x";
  auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
  const std::string path = dir.file("plain/c.h5");
  const std::string message = thrown_message([&] { write_checkpoint(path, contents_of(*simulation), kWriter); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
}

TEST(CheckpointFile, FailedWriteLeavesTheExistingCheckpointIntact) {
  TempDir dir;
  // A name so long (250 of the 255 bytes a name may have) that no temporary name beside it can be
  // created, whoever runs the test (root included); the checkpoint itself is put there by rename.
  const std::string path = dir.file(std::string(247, 'c') + ".h5");
  auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
  write_checkpoint(dir.file("c.h5"), contents_of(*simulation), kWriter);
  fs::rename(dir.file("c.h5"), path);
  const std::string before = file_bytes(path);
  simulation->run(5);
  const std::string message = thrown_message([&] { write_checkpoint(path, contents_of(*simulation), kWriter); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("File name too long"), std::string::npos) << message;
  EXPECT_EQ(file_bytes(path), before);
  EXPECT_EQ(read_checkpoint(path).state.step, 0);
  EXPECT_EQ(dir.entries().size(), 1u);
}

// In a child process (it cannot be undone), gives up what lets root write into any directory:
// becomes nobody (uid and gid 65534, no supplementary groups) when running as root and `dir` and
// its parents let others through; then clears every capability (a no-op after that setuid). Where
// nobody cannot be taken (a user namespace that maps no uid 65534) or could not reach `dir`, this
// leaves uid 0 without capabilities: without CAP_DAC_OVERRIDE root is held to the mode bits like
// any user. Returns how the process now runs, or "" and sets `error`.
std::string drop_write_privileges(const fs::path& dir, std::string& error) {
  bool others_reach = true;
  for (fs::path p = dir; !p.empty() && p != p.root_path(); p = p.parent_path()) {
    struct stat st {};
    if (::stat(p.c_str(), &st) != 0 || (st.st_mode & S_IXOTH) == 0) others_reach = false;
  }
  std::string how = "uid " + std::to_string(::geteuid());
  if (::geteuid() == 0 && others_reach && ::setgroups(0, nullptr) == 0 && ::setgid(65534) == 0 &&
      ::setuid(65534) == 0)
    how = "uid 65534 (nobody)";
  __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
  __user_cap_data_struct none[_LINUX_CAPABILITY_U32S_3] = {};
  if (::syscall(SYS_capset, &header, none) != 0) {
    error = std::string("capset: ") + std::strerror(errno);
    return "";
  }
  return how + " without capabilities";
}

// A directory the writer may not write into: the write fails naming the path and the reason, and
// the checkpoint already there is kept as it was. CI runs as root, whom a directory's mode does not
// stop, so the write is made in a child process that first gives that privilege up
// (drop_write_privileges) and checks that it can read the checkpoint but not create a file beside
// it (a child that could is a failure of this test, never a skip); the child sends what the write
// threw through a pipe and ends with _Exit (no HDF5 shutdown, no gtest in the child). The
// simulation is destroyed before fork: no thread but this one.
TEST(CheckpointFile, UnwritableDirectoryKeepsTheExistingCheckpoint) {
  TempDir dir;
  const fs::path sub = fs::path(dir.file("sub"));
  const std::string path = (sub / "c.h5").string();
  fs::create_directory(sub);
  CheckpointContents later;
  {
    auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
    write_checkpoint(path, contents_of(*simulation), kWriter);
    simulation->run(5);
    later = contents_of(*simulation);
  }
  const std::string before = file_bytes(path);
  using fs::perms;
  fs::permissions(sub.parent_path(), perms::owner_all | perms::group_read | perms::group_exec |
                                         perms::others_read | perms::others_exec);
  // The checkpoint itself stays writable for the writer (as for a user who owns it in a directory
  // made read-only): a writer that wrote it in place, the directory refusing its temporary file,
  // would damage it and fail below.
  fs::permissions(path, perms::owner_read | perms::owner_write | perms::group_read | perms::group_write |
                            perms::others_read | perms::others_write);
  const perms read_only = perms::owner_read | perms::owner_exec | perms::group_read | perms::group_exec |
                          perms::others_read | perms::others_exec;
  fs::permissions(sub, read_only);

  int channel[2];
  ASSERT_EQ(::pipe(channel), 0) << std::strerror(errno);
  std::fflush(nullptr);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0) << std::strerror(errno);
  if (child == 0) {
    ::close(channel[0]);
    const auto report = [&](int code, const std::string& text) {
      for (std::size_t done = 0; done < text.size();) {
        const ssize_t n = ::write(channel[1], text.data() + done, text.size() - done);
        if (n <= 0) break;
        done += static_cast<std::size_t>(n);
      }
      std::_Exit(code);
    };
    std::string error;
    const std::string how = drop_write_privileges(sub, error);
    if (how.empty()) report(2, "cannot give up the privilege to write anywhere: " + error);
    if (::access(path.c_str(), R_OK) != 0)
      report(2, how + ": cannot read " + path + ": " + std::strerror(errno));
    const std::string probe = (sub / "probe").string();
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd >= 0) {
      ::close(fd);
      ::unlink(probe.c_str());
      report(2, how + ": " + sub.string() + " is still writable");
    }
    try {
      write_checkpoint(path, later, kWriter);
    } catch (const std::exception& e) {
      report(0, how + "\n" + e.what());
    }
    report(1, how + "\n(nothing thrown)");
  }
  ::close(channel[1]);
  std::string received;
  char buffer[4096];
  for (ssize_t n; (n = ::read(channel[0], buffer, sizeof buffer)) != 0;) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    received.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(channel[0]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  fs::permissions(sub, perms::owner_all, fs::perm_options::add);
  ASSERT_TRUE(WIFEXITED(status)) << "the writer did not exit (status " << status << "): " << received;
  ASSERT_NE(WEXITSTATUS(status), 2) << "the test could not make the directory unwritable: " << received;
  const std::string how = received.substr(0, received.find('\n'));
  const std::string message = received.substr(std::min(received.size(), how.size() + 1));
  std::printf("[ writer   ] %s\n", how.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 0) << "writing into an unwritable directory succeeded";
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("Permission denied"), std::string::npos) << message;
  EXPECT_TRUE(file_bytes(path) == before) << "the existing checkpoint was changed";
  EXPECT_EQ(read_checkpoint(path).state.step, 0);
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(sub)) left.push_back(entry.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"c.h5"});
}

// While alive, files of this process cannot grow beyond `bytes` (a full disk, as the file system
// reports it: write fails with EFBIG instead of the signal).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &previous_);
    previous_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limited = previous_;
    limited.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limited);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &previous_);
    std::signal(SIGXFSZ, previous_handler_);
  }

 private:
  rlimit previous_{};
  void (*previous_handler_)(int) = nullptr;
};

// A checkpoint that cannot be completed reports failure, keeps the old file and leaves no
// temporary file. In a child process that ends with _Exit: after a failed write HDF5 1.10 crashes
// in its shutdown at exit (H5F__close_cb on the file it could not close), with or without this
// fix; the write itself, and everything after it but that shutdown, is unaffected.
TEST(CheckpointFile, WriteThatRunsOutOfSpaceFailsAndKeepsTheOldFile) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const auto write_without_space = [] {
    TempDir dir;
    const std::string path = dir.file("c.h5");
    auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
    write_checkpoint(path, contents_of(*simulation), kWriter);
    const std::string before = file_bytes(path);
    simulation->run(5);
    std::string message;
    {
      const FileSizeLimit limit(before.size() / 2);
      message = thrown_message([&] { write_checkpoint(path, contents_of(*simulation), kWriter); });
    }
    const bool kept = file_bytes(path) == before && dir.entries() == std::vector<std::string>{"c.h5"};
    const bool reported = message.find(path) != std::string::npos;
    std::fprintf(stderr, "kept the old file and nothing else: %d; failure named the path: %d (%s)\n", kept, reported,
                 message.c_str());
    std::error_code ignored;
    fs::remove_all(fs::path(path).parent_path(), ignored);  // _Exit skips ~TempDir
    std::_Exit(kept && reported ? 0 : 1);
  };
  EXPECT_EXIT(write_without_space(), ::testing::ExitedWithCode(0), "kept the old file and nothing else: 1");
}

TEST(TextFileReplacing, WriteThatRunsOutOfSpaceFailsAndKeepsTheOldFile) {
  TempDir dir;
  const std::string path = dir.file("index.xdmf");
  write_text_file_replacing(path, "old\n");
  std::string message;
  {
    const FileSizeLimit limit(64 * 1024);
    message = thrown_message([&] { write_text_file_replacing(path, std::string(1 << 20, 'x')); });
  }
  EXPECT_NE(message.find("File too large"), std::string::npos) << message;
  EXPECT_EQ(file_bytes(path), "old\n");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"index.xdmf"});
}

// What the daemon's clean-up at start relies on: every temporary name holds ".tmp-", lies beside
// its target and is new; none outlives its writer unless it became the target.
TEST(TemporaryFile, IsNewBesideItsTargetAndMarked) {
  TempDir dir;
  const std::string target = dir.file("c.h5");
  {
    const TemporaryFile a(target), b(target);
    EXPECT_NE(a.path(), b.path());
    for (const std::string& p : {a.path(), b.path()}) {
      EXPECT_EQ(p.rfind(target + std::string(kTemporaryMarker), 0), 0u) << p;
      EXPECT_TRUE(fs::is_regular_file(p)) << p;
    }
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{});
}

TEST(CheckpointFile, FailedRenameRemovesTheTemporaryFile) {
  TempDir dir;
  const std::string path = dir.file("c.h5");
  fs::create_directory(path);  // rename cannot replace a non-empty directory
  std::ofstream(path + "/keep") << "x";
  auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
  const std::string message = thrown_message([&] { write_checkpoint(path, contents_of(*simulation), kWriter); });
  EXPECT_NE(message.find("cannot rename"), std::string::npos) << message;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"c.h5"});
}

TEST(CheckpointFile, MissingOrForeignFilesAreRefusedClearly) {
  TempDir dir;
  EXPECT_NE(thrown_message([&] { read_checkpoint(dir.file("absent.h5")); }).find("no such file"), std::string::npos);
  std::ofstream(dir.file("text.h5")) << "not hdf5\n";
  EXPECT_NE(thrown_message([&] { read_checkpoint(dir.file("text.h5")); }).find("not an HDF5 file"), std::string::npos);
  {
    h5::File other(H5Fcreate(dir.file("other.h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
    ASSERT_TRUE(other.valid());
    h5::write_attribute(other.get(), "format_version", 1);
  }
  const std::string message = thrown_message([&] { read_checkpoint(dir.file("other.h5")); });
  EXPECT_NE(message.find("not an lbsolid checkpoint"), std::string::npos) << message;
  EXPECT_NE(message.find(dir.file("other.h5")), std::string::npos) << message;
}

// A file written by lbsolidd before owners existed (format 2; tests/server/data/README.md) is still
// read, whole and verified, as the local owner's.
TEST(CheckpointFile, Format2FilesFromBeforeOwnersAreReadAsTheLocalOwners) {
  const CheckpointContents old = read_checkpoint(std::string(LBSOLID_TEST_DATA_DIR) + "/checkpoint_format2.h5");
  EXPECT_EQ(old.owner, "local");
  EXPECT_EQ(old.session_id, "s-0f9de15af72d8daab098767e2e1df2c8");
  EXPECT_EQ(old.request_id, "fixture-v2");
  EXPECT_EQ(old.session_name, "format 2 fixture");
  EXPECT_TRUE(old.done);
  EXPECT_EQ(old.state.step, 20);
  EXPECT_EQ(old.target_step, 20);
  ASSERT_TRUE(old.state.has_fluid);
  EXPECT_EQ(old.state.fluid.cells, 16 * 8);
}

TEST(CheckpointFile, NewerFormatVersionIsRefusedNamingTheVersionRead) {
  TempDir dir;
  const std::string path = dir.file("c.h5");
  auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
  write_checkpoint(path, contents_of(*simulation), kWriter);
  {
    h5::File file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT));
    ASSERT_TRUE(file.valid());
    ASSERT_GE(H5Adelete(file.get(), "format_version"), 0);
    h5::write_attribute(file.get(), "format_version", 99);
  }
  const std::string message = thrown_message([&] { read_checkpoint(path); });
  EXPECT_NE(message.find("version 99"), std::string::npos) << message;
  EXPECT_NE(message.find("version " + std::to_string(kCheckpointFormatVersion)), std::string::npos) << message;
  EXPECT_NE(message.find(path), std::string::npos) << message;
}

TEST(CheckpointFile, DatasetOfTheWrongSizeIsRefused) {
  TempDir dir;
  const std::string path = dir.file("c.h5");
  auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
  CheckpointContents contents = contents_of(*simulation);
  contents.state.solid.momentum.resize(1);
  EXPECT_NE(thrown_message([&] { write_checkpoint(path, contents, kWriter); }).find("momenta"), std::string::npos);
  // The same file with valid checksums (the layout writer checks nothing) is refused on reading.
  write_checkpoint_layout(path, contents, kWriter);
  const std::string message = thrown_message([&] { read_checkpoint(path); });
  EXPECT_NE(message.find("momenta"), std::string::npos) << message;
}

// --- field snapshots --------------------------------------------------------------------------

scene::FluidFields fields_after(long steps, scene::Simulation& simulation) {
  simulation.run(steps);
  return simulation.fluid_fields();
}

TEST(FieldSnapshot, DatasetsHoldTheFieldsInZyxOrder) {
  TempDir dir;
  scene::Scene s = coupled_scene(LatticeKind::kD3Q19, Precision::kDouble);
  s.fluid.nx = 10;
  s.fluid.ny = 8;
  s.fluid.nz = 5;
  s.bodies[0].centre = {5, 4, 2};
  auto simulation = scene::build_simulation(s);
  const scene::FluidFields fields = fields_after(7, *simulation);
  append_field_snapshot(dir.file("fields.h5"), fields, 7, {});
  h5::File file(H5Fopen(dir.file("fields.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  ASSERT_TRUE(file.valid());
  const auto density = h5::read_dataset<double>(file.get(), "fields/step_000000000007/density");
  const auto velocity = h5::read_dataset<double>(file.get(), "fields/step_000000000007/velocity");
  EXPECT_EQ(density.dims, (std::vector<hsize_t>{5, 8, 10}));
  EXPECT_EQ(velocity.dims, (std::vector<hsize_t>{5, 8, 10, 3}));
  EXPECT_TRUE(same_bytes(density.values, fields.density));
  EXPECT_TRUE(same_bytes(velocity.values, fields.velocity));
}

// One XML element: its attributes and the text up to the next tag.
struct XmlElement {
  std::map<std::string, std::string> attributes;
  std::string text;
};

// Every <tag ...> element of xml in document order. Enough XML for the flat, entity-free text the
// XDMF writer emits: attributes are name="value", and no value holds '>'.
std::vector<XmlElement> xml_elements(const std::string& xml, const std::string& tag) {
  std::vector<XmlElement> found;
  const std::string open = "<" + tag;
  for (std::size_t at = xml.find(open); at != std::string::npos; at = xml.find(open, at + 1)) {
    const char after = xml[at + open.size()];
    if (after != ' ' && after != '>' && after != '/') continue;  // a longer tag name
    const std::size_t end = xml.find('>', at);
    XmlElement element;
    for (std::size_t pos = at, eq; (eq = xml.find("=\"", pos)) < end;) {
      const std::size_t name = xml.rfind(' ', eq) + 1;
      const std::size_t close = xml.find('"', eq + 2);
      element.attributes[xml.substr(name, eq - name)] = xml.substr(eq + 2, close - eq - 2);
      pos = close + 1;
    }
    if (xml[end - 1] != '/') element.text = xml.substr(end + 1, xml.find('<', end) - end - 1);
    found.push_back(element);
  }
  return found;
}

std::vector<std::string> attribute_of_each(const std::vector<XmlElement>& elements, const std::string& name) {
  std::vector<std::string> values;
  for (const XmlElement& e : elements) values.push_back(e.attributes.count(name) ? e.attributes.at(name) : "(none)");
  return values;
}

TEST(FieldSnapshot, XdmfListsEverySnapshotAsATimestep) {
  TempDir dir;
  scene::Scene s = coupled_scene(LatticeKind::kD2Q7, Precision::kDouble);
  auto simulation = scene::build_simulation(s);
  const std::string h5_path = dir.file("run.fields.h5");
  const SnapshotGeometry geometry{{1, 0.8660254037844386, 1}, {0.5, 0, 0}};
  append_field_snapshot(h5_path, fields_after(10, *simulation), 10, geometry);
  append_field_snapshot(h5_path, fields_after(10, *simulation), 20, geometry);
  EXPECT_EQ(xdmf_path_for(h5_path), dir.file("run.fields.xdmf"));
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"run.fields.h5", "run.fields.xdmf"}));

  const std::string xdmf = file_bytes(xdmf_path_for(h5_path));
  const std::vector<XmlElement> grids = xml_elements(xdmf, "Grid");
  ASSERT_EQ(grids.size(), 3u);  // the temporal collection and one grid per snapshot
  EXPECT_EQ(grids[0].attributes.at("GridType"), "Collection");
  EXPECT_EQ(grids[0].attributes.at("CollectionType"), "Temporal");
  EXPECT_EQ(attribute_of_each(xml_elements(xdmf, "Time"), "Value"), (std::vector<std::string>{"10", "20"}));
  const std::string nz_ny_nx = "1 12 16";
  const std::vector<XmlElement> topologies = xml_elements(xdmf, "Topology");
  EXPECT_EQ(attribute_of_each(topologies, "TopologyType"), (std::vector<std::string>(2, "3DCoRectMesh")));
  EXPECT_EQ(attribute_of_each(topologies, "Dimensions"), (std::vector<std::string>(2, nz_ny_nx)));
  EXPECT_EQ(attribute_of_each(xml_elements(xdmf, "Geometry"), "GeometryType"),
            (std::vector<std::string>(2, "ORIGIN_DXDYDZ")));
  const std::vector<XmlElement> attributes = xml_elements(xdmf, "Attribute");
  EXPECT_EQ(attribute_of_each(attributes, "Name"),
            (std::vector<std::string>{"density", "velocity", "density", "velocity"}));
  EXPECT_EQ(attribute_of_each(attributes, "AttributeType"),
            (std::vector<std::string>{"Scalar", "Vector", "Scalar", "Vector"}));
  EXPECT_EQ(attribute_of_each(attributes, "Center"), (std::vector<std::string>(4, "Node")));

  std::vector<std::string> hdf_dimensions, hdf_paths, origins, spacings;
  for (const XmlElement& item : xml_elements(xdmf, "DataItem")) {
    if (item.attributes.at("Format") == "HDF") {
      hdf_dimensions.push_back(item.attributes.at("Dimensions"));
      hdf_paths.push_back(item.text);
    } else {
      (item.attributes.at("Name") == "Origin" ? origins : spacings).push_back(item.text);
    }
  }
  EXPECT_EQ(hdf_dimensions, (std::vector<std::string>{nz_ny_nx, nz_ny_nx + " 3", nz_ny_nx, nz_ny_nx + " 3"}));
  EXPECT_EQ(hdf_paths, (std::vector<std::string>{"run.fields.h5:/fields/step_000000000010/density",
                                                 "run.fields.h5:/fields/step_000000000010/velocity",
                                                 "run.fields.h5:/fields/step_000000000020/density",
                                                 "run.fields.h5:/fields/step_000000000020/velocity"}));
  // z y x order.
  EXPECT_EQ(origins, (std::vector<std::string>(2, "0 0 0.5")));
  EXPECT_EQ(spacings, (std::vector<std::string>(2, "1 0.8660254037844386 1")));
}

TEST(FieldSnapshot, DuplicateStepOrOtherShapeIsRefused) {
  TempDir dir;
  auto simulation = scene::build_simulation(coupled_scene(LatticeKind::kD2Q9, Precision::kDouble));
  const std::string h5_path = dir.file("fields.h5");
  const scene::FluidFields fields = fields_after(1, *simulation);
  append_field_snapshot(h5_path, fields, 1, {});
  EXPECT_THROW(append_field_snapshot(h5_path, fields, 1, {}), std::invalid_argument);
  scene::FluidFields smaller = fields;
  smaller.shape = {8, 12, 1};
  smaller.density.resize(8 * 12);
  smaller.velocity.resize(3 * 8 * 12);
  EXPECT_THROW(append_field_snapshot(h5_path, smaller, 2, {}), std::invalid_argument);
  EXPECT_EQ(attribute_of_each(xml_elements(file_bytes(xdmf_path_for(h5_path)), "Time"), "Value"),
            std::vector<std::string>{"1"});
}

// --- H5MD -------------------------------------------------------------------------------------

constexpr int kParticles = 5;
constexpr int kFrames = 3;

// Frame f of particle p, component d: distinct and exact in binary.
double sample(int frame, int particle, int component) { return frame + 0.25 * particle + 0.0625 * component; }

void write_sample_trajectory(H5mdWriter& writer) {
  for (int f = 0; f < kFrames; ++f) {
    std::vector<double> positions, velocities;
    for (int p = 0; p < kParticles; ++p)
      for (int d = 0; d < 2; ++d) {
        positions.push_back(sample(f, p, d));
        velocities.push_back(-sample(f, p, d));
      }
    writer.append_particles("disk", 100 * f, positions, velocities);
    writer.append_body("disk", 100 * f, {1.5 + f, 2.5, 0}, {0.125, -0.25 * f, 0});
    writer.append_rotation("disk", 100 * f, {0, 0, 2.0 * f}, {0, 0, -0.5 * f}, 0.25 * f, {1.0 - f, 0, 0, 0.5 * f},
                           {0, 0, 0.125 * f});
    writer.append_profile(100 * f, {0, 1, 2, 3}, {0.0, 0.1 * f, 0.2 * f, 0.0});
  }
}

const H5mdBox kBox{2, {16, 12, 1}, {true, false, true}};

TEST(H5mdFile, HasTheH5mdStructure) {
  TempDir dir;
  const std::string path = dir.file("traj.h5md");
  const std::string scenario(100 * 1024, 'x');  // over the 64 KiB limit of compact attributes
  {
    H5mdWriter writer(path, "0.1.0", scenario, kBox);
    write_sample_trajectory(writer);
    writer.close();
  }
  h5::File file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  ASSERT_TRUE(file.valid());
  const h5::Group h5md = h5::open_group(file.get(), "h5md");
  EXPECT_EQ(h5::read_attribute_values<int>(h5md.get(), "version"), (std::vector<int>{1, 1}));
  EXPECT_FALSE(h5::read_string_attribute(h5::open_group(file.get(), "h5md/author").get(), "name").empty());
  const h5::Group creator = h5::open_group(file.get(), "h5md/creator");
  EXPECT_EQ(h5::read_string_attribute(creator.get(), "name"), "lbsolid");
  EXPECT_EQ(h5::read_string_attribute(creator.get(), "version"), "0.1.0");
  EXPECT_EQ(h5::read_string_attribute(h5::open_group(file.get(), "parameters").get(), "scenario"), scenario);

  const h5::Group box = h5::open_group(file.get(), "particles/disk/box");
  EXPECT_EQ(h5::read_attribute<int>(box.get(), "dimension"), 2);
  EXPECT_EQ(h5::read_dataset<double>(box.get(), "edges").values, (std::vector<double>{16, 12}));
  EXPECT_EQ(h5::read_dataset<double>(file.get(), "particles/disk/position/value").dims,
            (std::vector<hsize_t>{kFrames, kParticles, 2}));
  EXPECT_EQ(h5::read_dataset<long>(file.get(), "particles/disk/position/step").dims, (std::vector<hsize_t>{kFrames}));
  EXPECT_EQ(h5::read_dataset<double>(file.get(), "particles/disk/position/time").dims, (std::vector<hsize_t>{kFrames}));
  EXPECT_EQ(h5::read_dataset<double>(file.get(), "observables/disk/centre_of_mass/value").dims,
            (std::vector<hsize_t>{kFrames, 2}));
  EXPECT_EQ(h5::read_dataset<double>(file.get(), "observables/velocity_profile/value").dims,
            (std::vector<hsize_t>{kFrames, 4}));
  EXPECT_EQ(h5::read_dataset<double>(file.get(), "observables/velocity_profile_y").values,
            (std::vector<double>{0, 1, 2, 3}));
}

TEST(H5mdFile, SeriesReadBackExactly) {
  TempDir dir;
  const std::string path = dir.file("traj.h5md");
  {
    H5mdWriter writer(path, "0.1.0", "scenario", kBox);
    write_sample_trajectory(writer);
  }  // the destructor closes
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"traj.h5md", "traj.xdmf"}));
  const H5mdSeries position = read_h5md_series(path, "/particles/disk/position");
  EXPECT_EQ(position.step, (std::vector<long>{0, 100, 200}));
  EXPECT_EQ(position.time, (std::vector<double>{0, 100, 200}));
  EXPECT_EQ(position.value_shape, (std::vector<long>{kParticles, 2}));
  ASSERT_EQ(position.value.size(), std::size_t{kFrames * kParticles * 2});
  for (int f = 0; f < kFrames; ++f)
    for (int p = 0; p < kParticles; ++p)
      for (int d = 0; d < 2; ++d) EXPECT_EQ(position.value[(f * kParticles + p) * 2 + d], sample(f, p, d));
  const H5mdSeries velocity = read_h5md_series(path, "/observables/disk/velocity");
  EXPECT_EQ(velocity.value_shape, (std::vector<long>{2}));
  EXPECT_EQ(velocity.value, (std::vector<double>{0.125, 0, 0.125, -0.25, 0.125, -0.5}));
  // Rotation: 3-vectors whatever the box's dimension (2D: along z), the orientation one value.
  const H5mdSeries spin = read_h5md_series(path, "/observables/disk/angular_velocity");
  EXPECT_EQ(spin.value_shape, (std::vector<long>{3}));
  EXPECT_EQ(spin.value, (std::vector<double>{0, 0, 0, 0, 0, -0.5, 0, 0, -1}));
  EXPECT_EQ(read_h5md_series(path, "/observables/disk/angular_momentum").value[8], 4.0);
  const H5mdSeries orientation = read_h5md_series(path, "/observables/disk/orientation");
  EXPECT_EQ(orientation.value_shape, (std::vector<long>{1}));
  EXPECT_EQ(orientation.value, (std::vector<double>{0, 0.25, 0.5}));
  const H5mdSeries quaternion = read_h5md_series(path, "/observables/disk/orientation_quaternion");
  EXPECT_EQ(quaternion.value_shape, (std::vector<long>{4}));
  EXPECT_EQ(quaternion.value, (std::vector<double>{1, 0, 0, 0, 0, 0, 0, 0.5, -1, 0, 0, 1}));
  EXPECT_EQ(read_h5md_series(path, "/observables/disk/torque").value, (std::vector<double>{0, 0, 0, 0, 0, 0.125, 0, 0, 0.25}));
  const std::string message = thrown_message([&] { read_h5md_series(path, "/observables/none"); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("/observables/none"), std::string::npos) << message;
}

TEST(H5mdFile, AppearsUnderItsFinalNameOnlyWhenClosed) {
  TempDir dir;
  const std::string path = dir.file("traj.h5md");
  H5mdWriter writer(path, "0.1.0", "scenario", kBox);
  write_sample_trajectory(writer);
  writer.flush();
  EXPECT_FALSE(fs::exists(path));
  const auto partial = dir.entries();
  ASSERT_EQ(partial.size(), 1u);
  EXPECT_EQ(partial[0].rfind("traj.h5md.partial-", 0), 0u) << partial[0];
  writer.close();
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"traj.h5md", "traj.xdmf"}));
  EXPECT_THROW(writer.append_body("disk", 400, {0, 0, 0}, {0, 0, 0}), std::logic_error);
}

// Frames are written a chunk at a time (128 frames of a 2-vector, 4 of a 1,000-particle body): a
// run longer than several chunks, flushed once in the middle of one, reads back frame for frame.
TEST(H5mdFile, ManyFramesAcrossChunksAndAFlushReadBackExactly) {
  TempDir dir;
  const std::string path = dir.file("long.h5md");
  constexpr int kLongFrames = 301, kFlushAt = 150, kBodyParticles = 1000;
  {
    H5mdWriter writer(path, "0.1.0", "scenario", kBox);
    for (int f = 0; f < kLongFrames; ++f) {
      if (f == kFlushAt) writer.flush();
      std::vector<double> positions(2 * kBodyParticles), velocities(2 * kBodyParticles);
      for (int i = 0; i < 2 * kBodyParticles; ++i) {
        positions[i] = f + i / 4096.0;
        velocities[i] = -positions[i];
      }
      writer.append_particles("sheet", 3 * f, positions, velocities);
      writer.append_body("sheet", 3 * f, {f + 0.5, -0.25 * f, 0}, {0.125 * f, 1.0, 0});
    }
  }
  const H5mdSeries centre = read_h5md_series(path, "/observables/sheet/centre_of_mass");
  const H5mdSeries velocity = read_h5md_series(path, "/particles/sheet/velocity");
  ASSERT_EQ(centre.step.size(), std::size_t{kLongFrames});
  ASSERT_EQ(velocity.step.size(), std::size_t{kLongFrames});
  ASSERT_EQ(velocity.value.size(), std::size_t{kLongFrames * 2 * kBodyParticles});
  for (int f = 0; f < kLongFrames; ++f) {
    EXPECT_EQ(centre.step[f], 3 * f);
    EXPECT_EQ(centre.time[f], 3.0 * f);
    EXPECT_EQ(velocity.step[f], 3 * f);
    EXPECT_EQ(centre.value[2 * f], f + 0.5);
    EXPECT_EQ(centre.value[2 * f + 1], -0.25 * f);
    for (int i = 0; i < 2 * kBodyParticles; i += 333)
      EXPECT_EQ(velocity.value[std::size_t(f) * 2 * kBodyParticles + i], -(f + i / 4096.0)) << f << " " << i;
  }
}

// Two runs recording into one path at once (two `lbsolid submit --out` of one directory): each
// writes a file of its own, and the path ends as one of them, whole, never a mix (with one shared
// .partial name the second writer truncated the first's file under it).
TEST(H5mdFile, TwoWritersOfOnePathEachWriteTheirOwnFile) {
  TempDir dir;
  const std::string path = dir.file("traj.h5md");
  H5mdWriter first(path, "0.1.0", "scenario", kBox);
  H5mdWriter second(path, "0.1.0", "scenario", kBox);
  write_sample_trajectory(first);
  second.append_body("disk", 7, {1, 2}, {3, 4});
  second.close();
  EXPECT_EQ(read_h5md_series(path, "/observables/disk/velocity").step, (std::vector<long>{7}));
  first.close();  // the last to close gives the path its file
  EXPECT_EQ(read_h5md_series(path, "/particles/disk/position").step, (std::vector<long>{0, 100, 200}));
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"traj.h5md", "traj.xdmf"}));
}

// The XDMF beside an H5MD file with particles (xdmf_text.h): a temporal collection, one step per
// recorded frame, and for each body there a Polyvertex grid whose geometry and velocity are
// hyperslabs of that frame. Checked against the H5MD file itself: every dataset named exists with
// the dimensions the XDMF states, every slab lies inside it at the frame of its step, and a body
// name with XML's special characters is escaped. Without particles there is no XDMF.
struct Slab {
  long start[3], count[3], dims[3];
  std::string dataset;
};

std::vector<Slab> slabs_of(const std::string& xdmf) {
  static const std::regex slab(
      "<DataItem Dimensions=\"3 3\" Format=\"XML\">(\\d+) (\\d+) (\\d+) 1 1 1 (\\d+) (\\d+) (\\d+)</DataItem>"
      "<DataItem Dimensions=\"(\\d+) (\\d+) (\\d+)\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">([^<]*)</DataItem>");
  std::vector<Slab> out;
  for (auto it = std::sregex_iterator(xdmf.begin(), xdmf.end(), slab); it != std::sregex_iterator(); ++it) {
    Slab s;
    for (int k = 0; k < 3; ++k) {
      s.start[k] = std::stol((*it)[1 + k]);
      s.count[k] = std::stol((*it)[4 + k]);
      s.dims[k] = std::stol((*it)[7 + k]);
    }
    s.dataset = (*it)[10];
    out.push_back(s);
  }
  return out;
}

TEST(H5mdFile, AnXdmfBesideItShowsTheParticlesToParaView) {
  TempDir dir;
  const std::string path = dir.file("run.h5"), odd = "tip<&\"'>", odd_escaped = "tip&lt;&amp;&quot;&apos;&gt;";
  {
    H5mdWriter writer(path, "0.1.0", "scenario", kBox);
    write_sample_trajectory(writer);  // "disk": 3 frames at steps 0, 100, 200
    writer.append_particles(odd, 100, {1, 2}, {0, 0});
    writer.append_particles(odd, 200, {1, 3}, {0, 1});
  }
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"run.h5", "run.xdmf"}));
  const std::string xdmf = file_bytes(dir.file("run.xdmf"));
  EXPECT_NE(xdmf.find("CollectionType=\"Temporal\""), std::string::npos);
  EXPECT_EQ(xdmf.find(odd), std::string::npos) << "the body name must be escaped";
  EXPECT_NE(xdmf.find("Name=\"" + odd_escaped + "\""), std::string::npos);
  // The steps in order, then per step the grids of the bodies with a frame there.
  std::vector<long> times;
  static const std::regex time("<Time Value=\"(\\d+)\"/>");
  for (auto it = std::sregex_iterator(xdmf.begin(), xdmf.end(), time); it != std::sregex_iterator(); ++it)
    times.push_back(std::stol((*it)[1]));
  EXPECT_EQ(times, (std::vector<long>{0, 100, 200}));
  const auto count = [&](const std::string& what) {
    std::size_t n = 0;
    for (auto at = xdmf.find(what); at != std::string::npos; at = xdmf.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("TopologyType=\"Polyvertex\""), 5u);  // disk at 3 steps, the other at 2
  EXPECT_EQ(count("GeometryType=\"XY\""), 5u);
  // 2D: a position and two velocity components per grid, each inside its dataset.
  const auto slabs = slabs_of(xdmf);
  ASSERT_EQ(slabs.size(), 15u);
  for (const Slab& s : slabs) {
    ASSERT_EQ(s.dataset.rfind("run.h5:/particles/", 0), 0u) << s.dataset;
    std::string group = s.dataset.substr(std::string("run.h5:").size());
    group = group.substr(0, group.rfind("/value"));
    if (const auto at = group.find(odd_escaped); at != std::string::npos) group.replace(at, odd_escaped.size(), odd);
    const H5mdSeries series = read_h5md_series(path, group);
    EXPECT_EQ(s.dims[0], static_cast<long>(series.step.size())) << group;
    EXPECT_EQ(s.dims[1], series.value_shape[0]) << group;
    EXPECT_EQ(s.dims[2], series.value_shape[1]) << group;
    EXPECT_LT(s.start[0], s.dims[0]) << group;
    EXPECT_EQ(s.count[0], 1) << group;
    EXPECT_EQ(s.count[1], s.dims[1]) << group;
    EXPECT_LE(s.start[2] + s.count[2], s.dims[2]) << group;
  }
  // The odd body's first frame is step 100: in the grid at Time 100 its slab starts at frame 0.
  const auto at_100 = xdmf.find("<Time Value=\"100\"/>");
  const auto odd_grid = xdmf.find("Name=\"" + odd_escaped, at_100);
  ASSERT_NE(odd_grid, std::string::npos);
  EXPECT_LT(xdmf.find("Format=\"XML\">0 0 0 1 1 1 1 1 2</DataItem>", odd_grid), xdmf.find("<Time Value=\"200\"/>"));

  // 3D: XYZ geometry and a velocity vector; no particles: no XDMF.
  const H5mdBox box3{3, {8, 8, 8}, {true, true, true}};
  {
    H5mdWriter writer(dir.file("ball.h5"), "0.1.0", "scenario", box3);
    writer.append_particles("ball", 0, {1, 2, 3, 4, 5, 6}, {0, 0, 1, 0, 0, 1});
  }
  const std::string xdmf3 = file_bytes(dir.file("ball.xdmf"));
  EXPECT_NE(xdmf3.find("GeometryType=\"XYZ\""), std::string::npos);
  EXPECT_NE(xdmf3.find("Name=\"velocity\" AttributeType=\"Vector\""), std::string::npos);
  { H5mdWriter writer(dir.file("profile.h5"), "0.1.0", "scenario", kBox); writer.append_profile(0, {0, 1}, {0, 0}); }
  EXPECT_FALSE(fs::exists(dir.file("profile.xdmf")));
}

TEST(H5mdFile, ChangingParticleCountIsRefused) {
  TempDir dir;
  H5mdWriter writer(dir.file("traj.h5md"), "0.1.0", "scenario", kBox);
  writer.append_particles("disk", 0, {0, 0, 1, 1}, {0, 0, 0, 0});
  EXPECT_THROW(writer.append_particles("disk", 1, {0, 0}, {0, 0}), std::invalid_argument);
  EXPECT_THROW(writer.append_particles("disk", 1, {0, 0, 1}, {0, 0, 0}), std::invalid_argument);
  writer.append_particles("disk", 1, {0, 0, 2, 2}, {0, 0, 0, 0});
  writer.close();
  EXPECT_EQ(read_h5md_series(dir.file("traj.h5md"), "/particles/disk/position").step, (std::vector<long>{0, 1}));
}

TEST(H5mdFile, UncreatableFileIsReportedWithThePath) {
  TempDir dir;
  const std::string path = dir.file("missing/traj.h5md");
  const std::string message = thrown_message([&] { H5mdWriter writer(path, "0.1.0", "scenario", kBox); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
}

}  // namespace
}  // namespace lbsolid::server::storage
