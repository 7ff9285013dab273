// Checkpoint integrity: a damaged checkpoint file is refused with a message naming what failed, or
// (when the damage hit bytes nothing reads) restores exactly what was written; a checkpoint that
// reads back is always a state a run can continue from (finite values, possible counters).
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "scene/restart_support.h"
#include "scene/simulation.h"
#include "io/storage/checkpoint_file.h"
#include "io/storage/checkpoint_layout.h"
#include "io/storage/checkpoint_validation.h"
#include "io/storage/hdf5_io.h"

namespace lbsolid::server::storage {
namespace {

namespace fs = std::filesystem;
using scene::LatticeKind;
using scene::Precision;
using scene::testing::same_bytes;

// A fresh directory under the system temporary directory, removed with everything in it.
class ScratchDir {
 public:
  ScratchDir() {
    static std::atomic<int> counter{0};
    path_ = fs::temp_directory_path() /
            ("lbsolid-integrity-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void put_file_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
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

// Small (so that metadata is a good part of the file) with every kind of dataset: a two-buffer
// fluid (current and both buffers matter), a disk (positions, incoming links, momenta).
CheckpointContents small_coupled_contents() {
  scene::Scene s =
      scene::testing::coupled_scene(LatticeKind::kD2Q9, Precision::kDouble, fluid::StreamingScheme::kTwoBuffer);
  s.fluid.nx = 10;
  s.fluid.ny = 8;
  s.bodies[0].centre = {5, 4, 0};
  auto simulation = scene::build_simulation(s);
  simulation->run(7);
  CheckpointContents contents;
  contents.scenario_text = "fluid {\n  nx: 10\n  ny: 8\n}\nname: \"integrity\"\n";
  contents.session_id = "s-000042";
  contents.session_name = "integrity";
  contents.request_id = "request-7";
  contents.target_step = 100;
  contents.state = simulation->save_state();
  return contents;
}

const WriterInfo kWriter{"0.1.0", "abc1234"};

// Bit for bit, everything read_checkpoint returns.
bool identical(const CheckpointContents& a, const CheckpointContents& b) {
  const scene::SimulationState &x = a.state, &y = b.state;
  return a.scenario_text == b.scenario_text && a.session_id == b.session_id && a.session_name == b.session_name &&
         a.request_id == b.request_id && a.done == b.done && a.started == b.started &&
         a.target_step == b.target_step && x.step == y.step &&
         x.has_fluid == y.has_fluid && x.fluid.steps == y.fluid.steps && x.fluid.current == y.fluid.current &&
         x.fluid.pulled == y.fluid.pulled && x.fluid.stepped == y.fluid.stepped && x.fluid.buffers == y.fluid.buffers &&
         x.fluid.cells == y.fluid.cells && same_bytes(x.fluid.populations, y.fluid.populations) &&
         x.has_solid == y.has_solid && same_bytes(x.solid.positions, y.solid.positions) &&
         same_bytes(x.solid.incoming, y.solid.incoming) && same_bytes(x.solid.momentum, y.solid.momentum);
}

// Where each dataset's values lie in the file ([offset, offset + size)).
struct Payload {
  std::string name;
  std::size_t offset = 0, size = 0;
};

std::vector<Payload> payloads_of(const std::string& path) {
  h5::File file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  EXPECT_TRUE(file.valid());
  std::vector<Payload> found;
  for (const char* name :
       {"/scenario", "/fluid/populations", "/solid/positions", "/solid/incoming", "/solid/momentum"}) {
    h5::Dataset dataset(H5Dopen2(file.get(), name, H5P_DEFAULT));
    EXPECT_TRUE(dataset.valid()) << name;
    const haddr_t offset = H5Dget_offset(dataset.get());
    EXPECT_NE(offset, HADDR_UNDEF) << name << " is not stored contiguously";
    found.push_back(
        {name, static_cast<std::size_t>(offset), static_cast<std::size_t>(H5Dget_storage_size(dataset.get()))});
  }
  return found;
}

// The bytes of the file outside every payload: HDF5's metadata, attributes, free space.
std::vector<std::size_t> metadata_bytes(std::size_t file_size, const std::vector<Payload>& payloads) {
  std::vector<bool> payload(file_size, false);
  for (const Payload& p : payloads)
    for (std::size_t i = p.offset; i < p.offset + p.size && i < file_size; ++i) payload[i] = true;
  std::vector<std::size_t> offsets;
  for (std::size_t i = 0; i < file_size; ++i)
    if (!payload[i]) offsets.push_back(i);
  return offsets;
}

// The central promise: no damaged checkpoint is accepted. 400 seeded trials, each on a fresh copy
// of a valid file: a flipped bit or a range of 1-64 random bytes, half of them anywhere (mostly
// population values) and half in the metadata (headers, attributes, links), where HDF5's own
// checksums and our root checksum must catch it. A trial passes when read_checkpoint throws
// std::runtime_error, or returns exactly what was written (the damage hit bytes nothing reads).
TEST(CheckpointIntegrity, NoDamagedFileIsAccepted) {
  ScratchDir dir;
  const std::string original_path = dir.file("original.h5");
  const CheckpointContents original = small_coupled_contents();
  write_checkpoint(original_path, original, kWriter);
  ASSERT_TRUE(identical(read_checkpoint(original_path), original));
  const std::string bytes = file_bytes(original_path);
  const std::vector<std::size_t> metadata = metadata_bytes(bytes.size(), payloads_of(original_path));
  ASSERT_FALSE(metadata.empty());

  std::mt19937_64 random(0x5eed2024);
  auto below = [&](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(random); };
  const std::string damaged_path = dir.file("damaged.h5");
  constexpr int kTrials = 400;
  int detected = 0, by_our_checksums = 0, harmless = 0;
  std::vector<std::string> accepted, wrong_exception;
  for (int trial = 0; trial < kTrials; ++trial) {
    std::string damaged = bytes;
    const bool in_metadata = trial % 2 == 1;
    const std::size_t at = in_metadata ? metadata[below(metadata.size())] : below(bytes.size());
    std::string what;
    if (trial % 4 < 2) {
      const int bit = static_cast<int>(below(8));
      damaged[at] = static_cast<char>(damaged[at] ^ (1 << bit));
      what = "bit " + std::to_string(bit) + " of byte " + std::to_string(at);
    } else {
      const std::size_t length = std::min<std::size_t>(1 + below(64), bytes.size() - at);
      for (std::size_t i = 0; i < length; ++i) damaged[at + i] = static_cast<char>(below(256));
      what = std::to_string(length) + " random bytes at " + std::to_string(at);
    }
    what = "trial " + std::to_string(trial) + ": " + what;
    put_file_bytes(damaged_path, damaged);
    try {
      const CheckpointContents read = read_checkpoint(damaged_path);
      if (identical(read, original)) {
        ++harmless;
      } else {
        accepted.push_back(what);
      }
    } catch (const std::runtime_error& e) {
      ++detected;
      if (std::string(e.what()).find("checksum mismatch") != std::string::npos) ++by_our_checksums;
    } catch (const std::exception& e) {
      wrong_exception.push_back(what + ": " + e.what());
    }
  }
  std::cout << "[ integrity ] " << kTrials << " damaged copies of a " << bytes.size() << "-byte checkpoint ("
            << metadata.size() << " bytes of metadata): " << detected << " refused (" << by_our_checksums
            << " by our checksums, the others by HDF5's or the format checks), " << harmless
            << " harmless (read back identical), " << accepted.size() << " accepted with other contents, "
            << wrong_exception.size() << " other exceptions\n";
  for (const std::string& a : accepted) ADD_FAILURE() << "damaged checkpoint accepted: " << a;
  for (const std::string& w : wrong_exception) ADD_FAILURE() << "not a std::runtime_error: " << w;
  EXPECT_EQ(detected + harmless, kTrials);
  EXPECT_GT(detected, kTrials / 2);  // most bytes matter: a test whose damage never lands proves nothing
}

// --- changes HDF5 cannot see ------------------------------------------------------------------

// A change made through HDF5 itself (a tool, a stray program) passes HDF5's own header checksums:
// only ours can catch it.
struct Rewrite {
  const char* what;
  std::function<void(hid_t file)> change;
  const char* message;
};

void rewrite_int_attribute(hid_t file, const char* object, const char* name, int value) {
  h5::Handle<H5Oclose> target(H5Oopen(file, object, H5P_DEFAULT));
  ASSERT_TRUE(target.valid()) << object;
  ASSERT_GE(H5Adelete(target.get(), name), 0) << name;
  h5::write_attribute(target.get(), name, value);
}

void rewrite_long_attribute(hid_t file, const char* object, const char* name, long value) {
  h5::Handle<H5Oclose> target(H5Oopen(file, object, H5P_DEFAULT));
  ASSERT_TRUE(target.valid()) << object;
  ASSERT_GE(H5Adelete(target.get(), name), 0) << name;
  h5::write_attribute(target.get(), name, value);
}

void rewrite_string_attribute(hid_t file, const char* object, const char* name, const std::string& value) {
  h5::Handle<H5Oclose> target(H5Oopen(file, object, H5P_DEFAULT));
  ASSERT_TRUE(target.valid()) << object;
  ASSERT_GE(H5Adelete(target.get(), name), 0) << name;
  h5::write_string_attribute(target.get(), name, value);
}

// Rewrites a float64 dataset in place (same extent), with one value changed.
void rewrite_value(hid_t file, const char* path, std::size_t index, double value) {
  h5::DatasetValues<double> data = h5::read_dataset<double>(file, path);
  ASSERT_LT(index, data.values.size());
  data.values[index] = value;
  h5::Dataset dataset(H5Dopen2(file, path, H5P_DEFAULT));
  ASSERT_GE(H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.values.data()), 0);
}

TEST(CheckpointIntegrity, ChangesMadeThroughHdf5AreRefusedByName) {
  ScratchDir dir;
  const CheckpointContents original = small_coupled_contents();
  const std::vector<Rewrite> rewrites = {
      {"one population",
       [&](hid_t f) { rewrite_value(f, "/fluid/populations", 5, original.state.fluid.populations[5] + 1); },
       "dataset /fluid/populations: checksum mismatch"},
      {"one position by an ulp",
       [&](hid_t f) {
         rewrite_value(f, "/solid/positions", 1, std::nextafter(original.state.solid.positions[0][1], 1e9));
       },
       "dataset /solid/positions: checksum mismatch"},
      {"one momentum",
       [&](hid_t f) { rewrite_value(f, "/solid/momentum", 0, original.state.solid.momentum[0][0] + 1); },
       "dataset /solid/momentum: checksum mismatch"},
      {"the scenario",
       [](hid_t f) {
         ASSERT_GE(H5Ldelete(f, "scenario", H5P_DEFAULT), 0);
         h5::write_string_dataset(f, "scenario", "fluid { nx: 11 }");
       },
       "dataset /scenario: missing attribute sha256"},
      {"a dataset's checksum",
       [](hid_t f) { rewrite_string_attribute(f, "/solid/incoming", "sha256", std::string(64, '0')); },
       "dataset /solid/incoming: checksum mismatch"},
      {"the step", [](hid_t f) { rewrite_long_attribute(f, "/", "step", 8); }, "root attributes: checksum mismatch"},
      {"the target", [](hid_t f) { rewrite_long_attribute(f, "/", "target_step", 1L << 40); },
       "root attributes: checksum mismatch"},
      {"the session name", [](hid_t f) { rewrite_string_attribute(f, "/", "session_name", "other"); },
       "root attributes: checksum mismatch"},
      {"done", [](hid_t f) { rewrite_int_attribute(f, "/", "done", 1); }, "root attributes: checksum mismatch"},
      {"done neither 0 nor 1", [](hid_t f) { rewrite_int_attribute(f, "/", "done", 2); },
       "root attribute done: 2 is not 0 or 1"},
      {"the fluid's current buffer", [](hid_t f) { rewrite_int_attribute(f, "/fluid", "current", 0); },
       "root attributes: checksum mismatch"},
      {"the fluid's pulled flag", [](hid_t f) { rewrite_int_attribute(f, "/fluid", "pulled", 1); },
       "root attributes: checksum mismatch"},
      {"the solid group removed", [](hid_t f) { ASSERT_GE(H5Ldelete(f, "solid", H5P_DEFAULT), 0); },
       "root attributes: checksum mismatch"},
      {"the root checksum removed", [](hid_t f) { ASSERT_GE(H5Adelete(f, "sha256"), 0); }, "missing attribute sha256"},
      {"the owner", [](hid_t f) { rewrite_string_attribute(f, "/", "owner", "mallory"); },
       "root attributes: checksum mismatch"},
      {"format version 3 read as 2 (no owner)", [](hid_t f) { rewrite_int_attribute(f, "/", "format_version", 2); },
       "root attributes: checksum mismatch"},
      {"format version 1", [](hid_t f) { rewrite_int_attribute(f, "/", "format_version", 1); },
       "checkpoint format version 1 has no checksums and is no longer read"},
      {"format version 0", [](hid_t f) { rewrite_int_attribute(f, "/", "format_version", 0); },
       "invalid checkpoint format version 0"},
  };
  ASSERT_EQ(original.state.fluid.current, 1);  // so "current 0" is a change
  ASSERT_FALSE(original.state.fluid.pulled);   // two buffers never pull: "pulled 1" is a change
  for (const Rewrite& rewrite : rewrites) {
    SCOPED_TRACE(rewrite.what);
    const std::string path = dir.file("c.h5");
    write_checkpoint(path, original, kWriter);
    {
      h5::File file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT));
      ASSERT_TRUE(file.valid());
      rewrite.change(file.get());
    }
    std::string message = "(nothing thrown)";
    try {
      read_checkpoint(path);
    } catch (const std::runtime_error& e) {
      message = e.what();
    }
    EXPECT_NE(message.find(rewrite.message), std::string::npos) << message;
    EXPECT_NE(message.find(path), std::string::npos) << message;
  }
}

// --- contents no run can continue from --------------------------------------------------------

struct Impossible {
  const char* what;
  std::function<void(CheckpointContents&)> change;
  const char* message;
};

// write_checkpoint refuses them (the old file stays); a file holding them with valid checksums
// (written by the layout writer, which checks nothing) is refused by read_checkpoint.
TEST(CheckpointIntegrity, ImpossibleContentsAreRefusedOnWritingAndReading) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const std::vector<Impossible> cases = {
      {"NaN population", [](auto& c) { c.state.fluid.populations[17] = kNaN; },
       "dataset /fluid/populations: value 17 is NaN"},
      {"infinite population", [](auto& c) { c.state.fluid.populations[3] = -kInfinity; },
       "dataset /fluid/populations: value 3 is -infinity"},
      {"step -1",
       [](auto& c) {
         c.state.step = -1;
         c.state.fluid.steps = -1;
       },
       "attribute step: -1 is negative"},
      {"step beyond 2^53",
       [](auto& c) {
         c.state.step = kMaxCheckpointStep + 1;
         c.state.fluid.steps = kMaxCheckpointStep + 1;
       },
       "attribute step: 9007199254740993 is beyond any possible run"},
      {"target -5", [](auto& c) { c.target_step = -5; }, "attribute target_step: -5 is negative"},
      {"fluid steps not the step", [](auto& c) { c.state.fluid.steps = 8; },
       "/fluid attribute steps: 8 differs from the step 7"},
      {"three buffers", [](auto& c) { c.state.fluid.buffers = 3; }, "/fluid attribute buffers: 3 is not 1"},
      {"current buffer 2 of 2", [](auto& c) { c.state.fluid.current = 2; },
       "/fluid attribute current: 2 is not a buffer"},
      {"current buffer -1", [](auto& c) { c.state.fluid.current = -1; },
       "/fluid attribute current: -1 is not a buffer"},
      {"negative cells", [](auto& c) { c.state.fluid.cells = -80; }, "/fluid attribute cells: -80 is not positive"},
      {"populations not whole", [](auto& c) { c.state.fluid.populations.pop_back(); },
       "dataset /fluid/populations: holds 1439 values"},
      {"NaN position", [](auto& c) { c.state.solid.positions[2][1] = kNaN; },
       "dataset /solid/positions: value 7 is NaN"},
      {"infinite incoming link", [](auto& c) { c.state.solid.incoming[0][0] = kInfinity; },
       "dataset /solid/incoming: value 0 is +infinity"},
      {"NaN momentum", [](auto& c) { c.state.solid.momentum[1][2] = kNaN; }, "dataset /solid/momentum: value 5 is NaN"},
  };
  ScratchDir dir;
  const CheckpointContents original = small_coupled_contents();
  ASSERT_EQ(original.state.step, 7);
  ASSERT_EQ(original.state.fluid.populations.size(), 2u * 9 * 80);
  const std::string kept = dir.file("kept.h5");
  write_checkpoint(kept, original, kWriter);
  const std::string kept_bytes = file_bytes(kept);
  for (const Impossible& impossible : cases) {
    SCOPED_TRACE(impossible.what);
    CheckpointContents contents = original;
    impossible.change(contents);
    const std::string written = thrown_message([&] { write_checkpoint(kept, contents, kWriter); });
    EXPECT_NE(written.find(impossible.message), std::string::npos) << written;
    EXPECT_EQ(file_bytes(kept), kept_bytes);

    const std::string path = dir.file("impossible.h5");
    write_checkpoint_layout(path, contents, kWriter);
    std::string read = "(nothing thrown)";
    try {
      read_checkpoint(path);
    } catch (const std::runtime_error& e) {
      read = e.what();
    }
    EXPECT_NE(read.find(impossible.message), std::string::npos) << read;
    EXPECT_NE(read.find(path), std::string::npos) << read;
  }
}

}  // namespace
}  // namespace lbsolid::server::storage
