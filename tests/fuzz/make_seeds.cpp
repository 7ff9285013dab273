// Seed corpora for the fuzz targets, made from the example scenarios:
//   make_seeds <scenario dir> <out dir>
// writes <out>/fuzz_scenario_text/<name>.textproto (the file as it is),
//        <out>/fuzz_scenario_json/<name>.json      (the same scenario through protobuf's JSON printer),
//        <out>/fuzz_scenario_binary/<name>.bin     (serialized),
//        <out>/fuzz_service/<name>.calls           (a session's life: create, get, step, checkpoint,
//                                                   restore, list, run, pause, resume, cancel, delete,
//                                                   server info; format in service_calls.h)
// for every <scenario dir>/*.textproto that parses (service seeds only for the scenarios within
// fuzz_service's limit of 8192 nodes).
#include <google/protobuf/util/json_util.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "fuzz/service_calls.h"
#include "lbsolid/v1/simulation.pb.h"
#include "io/api/scenario_translation.h"

namespace {

namespace fs = std::filesystem;
namespace v1 = lbsolid::v1;
using lbsolid::fuzz::encode_call;
using lbsolid::fuzz::Method;

void write(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
}

template <typename Request>
std::string with_session(const std::string& id) {
  Request request;
  request.set_session_id(id);
  return request.SerializeAsString();
}

// "$" + a byte: fuzz_service's reference to an id answered earlier in the input (service_calls.h).
std::string answered(int index) { return std::string("$") + static_cast<char>(index); }

std::string session_life(const v1::Scenario& scenario) {
  const std::string created = answered(0), restored = answered(1);
  std::string calls;
  v1::ValidateScenarioRequest validate;
  *validate.mutable_scenario() = scenario;
  calls += encode_call(Method::kValidateScenario, validate.SerializeAsString());
  v1::CreateSessionRequest create;
  *create.mutable_scenario() = scenario;
  create.set_request_id("seed");
  // Recorded by the daemon too (scenario.outputs), so that ListOutputs has files to make.
  if (create.scenario().bodies_size() > 0) create.mutable_scenario()->mutable_outputs()->set_particles_every(1);
  calls += encode_call(Method::kCreateSession, create.SerializeAsString());
  calls += encode_call(Method::kGetSession, with_session<v1::GetSessionRequest>(created));
  v1::StepRequest step;
  step.set_session_id(created);
  step.set_steps(2);
  calls += encode_call(Method::kStep, step.SerializeAsString());
  calls += encode_call(Method::kCheckpoint, with_session<v1::CheckpointRequest>(created));
  calls += encode_call(Method::kListOutputs, with_session<v1::ListOutputsRequest>(created));
  v1::RestoreRequest restore;
  restore.set_checkpoint_id(answered(0));
  calls += encode_call(Method::kRestore, restore.SerializeAsString());
  calls += encode_call(Method::kListSessions, "");
  v1::RunRequest run;
  run.set_session_id(restored);
  run.set_steps(50);
  calls += encode_call(Method::kRun, run.SerializeAsString());
  calls += encode_call(Method::kPause, with_session<v1::PauseRequest>(restored));
  calls += encode_call(Method::kResume, with_session<v1::ResumeRequest>(restored));
  calls += encode_call(Method::kCancel, with_session<v1::CancelRequest>(restored));
  calls += encode_call(Method::kDeleteSession, with_session<v1::DeleteSessionRequest>(created));
  calls += encode_call(Method::kGetServerInfo, "");
  return calls;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: make_seeds <scenario dir> <out dir>\n");
    return 2;
  }
  const fs::path scenarios(argv[1]), out(argv[2]);
  int made = 0;
  for (const auto& entry : fs::directory_iterator(scenarios)) {
    if (entry.path().extension() != ".textproto") continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    v1::Scenario scenario;
    std::string error;
    if (!lbsolid::server::parse_scenario_text(text, &scenario, &error)) {
      std::fprintf(stderr, "make_seeds: %s: %s (skipped)\n", entry.path().c_str(), error.c_str());
      continue;
    }
    const std::string stem = entry.path().stem().string();
    write(out / "fuzz_scenario_text" / (stem + ".textproto"), text);
    std::string json;
    google::protobuf::util::JsonPrintOptions options;
    options.add_whitespace = true;
    if (!google::protobuf::util::MessageToJsonString(scenario, &json, options).ok()) {
      std::fprintf(stderr, "make_seeds: %s: no JSON form\n", entry.path().c_str());
      return 1;
    }
    write(out / "fuzz_scenario_json" / (stem + ".json"), json);
    write(out / "fuzz_scenario_binary" / (stem + ".bin"), scenario.SerializeAsString());
    const long cells = long(scenario.domain().nx()) * std::max(1L, long(scenario.domain().ny())) *
                       std::max(1L, long(scenario.domain().nz()));
    if (cells <= 8192) write(out / "fuzz_service" / (stem + ".calls"), session_life(scenario));
    ++made;
  }
  std::printf("make_seeds: seeds from %d scenarios in %s\n", made, out.c_str());
  return made > 0 ? 0 : 1;
}
