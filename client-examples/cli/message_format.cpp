#include "message_format.h"

#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <numeric>
#include <vector>

#include "json_writer.h"

namespace lbsolid::cli {
namespace {

using lbsolid::v1::SessionState;

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

std::string vector_json(const lbsolid::v1::Vector3& v) { return json_array(std::vector<double>{v.x(), v.y(), v.z()}); }

std::string vector_text(const lbsolid::v1::Vector3& v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", v.x(), v.y(), v.z());
  return text;
}

std::string local_time(long long unix_ms) {
  const std::time_t seconds = static_cast<std::time_t>(unix_ms / 1000);
  std::tm tm{};
  localtime_r(&seconds, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S", &tm);
  return text;
}

}  // namespace

std::string state_name(SessionState state) {
  switch (state) {
    case lbsolid::v1::SESSION_STATE_CREATED: return "CREATED";
    case lbsolid::v1::SESSION_STATE_RUNNING: return "RUNNING";
    case lbsolid::v1::SESSION_STATE_PAUSED: return "PAUSED";
    case lbsolid::v1::SESSION_STATE_DONE: return "DONE";
    case lbsolid::v1::SESSION_STATE_FAILED: return "FAILED";
    case lbsolid::v1::SESSION_STATE_CANCELLED: return "CANCELLED";
    default: return "UNSPECIFIED";
  }
}

bool is_final(SessionState state) {
  return state == lbsolid::v1::SESSION_STATE_DONE || state == lbsolid::v1::SESSION_STATE_FAILED ||
         state == lbsolid::v1::SESSION_STATE_CANCELLED;
}

std::string scenario_json(const lbsolid::v1::Scenario& scenario) {
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  std::string json;
  if (!google::protobuf::util::MessageToJsonString(scenario, &json, options).ok()) return "null";
  return json;
}

std::string session_json(const lbsolid::v1::Session& s, bool with_scenario) {
  JsonObject o;
  o.string("id", s.id())
      .string("name", s.name())
      .string("state", state_name(s.state()))
      .integer("step", s.step())
      .integer("target_step", s.target_step())
      .string("message", s.message())
      .raw("stages", json_string_array({s.stages().begin(), s.stages().end()}))
      .integer("cells", s.cells())
      .integer("particles", s.particles())
      .integer("fluid_bytes", s.fluid_bytes())
      .integer("solid_bytes", s.solid_bytes())
      .number("steps_per_second", s.steps_per_second())
      .number("mlups", s.mlups())
      .integer("created_unix_ms", s.created_unix_ms())
      .string("request_id", s.request_id())
      .string("owner", s.owner())
      .string("endpoint", s.endpoint());
  if (with_scenario) o.raw("scenario", scenario_json(s.scenario()));
  return o.str();
}

CommandResult session_result(const std::string& command, const lbsolid::v1::Session& s, bool with_scenario) {
  CommandResult result;
  result.command = command;
  result.session_id = s.id();
  result.state = state_name(s.state());
  result.step = s.step();
  result.target_step = s.target_step();
  result.message = s.message();
  result.add("session", session_json(s, with_scenario));
  return result;
}

std::string session_line(const lbsolid::v1::Session& s) {
  char text[160];
  std::snprintf(text, sizeof text, "%-10s %-9s step %lld/%lld", s.id().c_str(), state_name(s.state()).c_str(),
                static_cast<long long>(s.step()), static_cast<long long>(s.target_step()));
  std::string line = text;
  if (!s.name().empty()) line += "  " + s.name();
  if (!s.message().empty()) line += "  (" + s.message() + ")";
  return line;
}

std::string session_text(const lbsolid::v1::Session& s) {
  std::string text = "session     " + s.id() + (s.name().empty() ? "" : "  " + s.name()) + "\n";
  text += "state       " + state_name(s.state()) + "\n";
  text += "step        " + std::to_string(s.step()) + " / " + std::to_string(s.target_step()) + "\n";
  if (!s.message().empty()) text += "message     " + s.message() + "\n";
  if (s.state() == lbsolid::v1::SESSION_STATE_RUNNING)
    text += "rate        " + format("%.1f", s.steps_per_second()) + " steps/s, " + format("%.2f", s.mlups()) +
            " MLUPS\n";
  std::string stages;
  for (const auto& stage : s.stages()) stages += (stages.empty() ? "" : ", ") + stage;
  text += "stages      " + stages + "\n";
  text += "size        " + std::to_string(s.cells()) + " cells, " + std::to_string(s.particles()) + " particles\n";
  text += "memory      " + format("%.1f", (s.fluid_bytes() + s.solid_bytes()) / 1048576.0) + " MiB (fluid " +
          format("%.1f", s.fluid_bytes() / 1048576.0) + ", solid " + format("%.1f", s.solid_bytes() / 1048576.0) +
          ")\n";
  if (s.created_unix_ms() > 0) text += "created     " + local_time(s.created_unix_ms()) + "\n";
  if (!s.request_id().empty()) text += "request id  " + s.request_id() + "\n";
  if (!s.endpoint().empty()) text += "endpoint    " + s.endpoint() + "\n";
  return text;
}

std::string server_info_json(const lbsolid::v1::ServerInfo& info) {
  return JsonObject()
      .string("version", info.version())
      .string("git_revision", info.git_revision())
      .string("api_version", info.api_version())
      .raw("capabilities", json_string_array({info.capabilities().begin(), info.capabilities().end()}))
      .integer("workers", info.workers())
      .integer("max_sessions", info.max_sessions())
      .integer("max_cells", info.max_cells())
      .integer("max_sync_steps", info.max_sync_steps())
      .integer("max_message_bytes", info.max_message_bytes())
      .integer("sessions", info.sessions())
      .integer("running_sessions", info.running_sessions())
      .string("endpoint", info.endpoint())
      .str();
}

std::string server_info_text(const lbsolid::v1::ServerInfo& info) {
  std::string capabilities;
  for (const auto& c : info.capabilities()) capabilities += (capabilities.empty() ? "" : " ") + c;
  return "version           " + info.version() + (info.git_revision().empty() ? "" : " (" + info.git_revision() + ")") +
         "\napi version       " + info.api_version() + "\ncapabilities      " + capabilities +
         "\nworkers           " + std::to_string(info.workers()) + "\nsessions          " +
         std::to_string(info.sessions()) + " of at most " + std::to_string(info.max_sessions()) +
         "\nmax cells         " + std::to_string(info.max_cells()) + "\nmax sync steps    " +
         std::to_string(info.max_sync_steps()) + "\nmax message bytes " + std::to_string(info.max_message_bytes()) +
         "\n";
}

std::string checkpoint_json(const lbsolid::v1::CheckpointResponse& c) {
  return JsonObject()
      .string("checkpoint_id", c.checkpoint_id())
      .string("path", c.path())
      .integer("step", c.step())
      .integer("bytes", c.bytes())
      .str();
}

std::string profile_frame_json(const lbsolid::v1::ProfileFrame& f) {
  return JsonObject()
      .integer("step", f.step())
      .integer("skipped_frames", f.skipped_frames())
      .raw("y", json_array(std::vector<double>(f.y().begin(), f.y().end())))
      .raw("u_x", json_array(std::vector<double>(f.u_x().begin(), f.u_x().end())))
      .str();
}

std::string profile_frame_text(const lbsolid::v1::ProfileFrame& f) {
  std::string text = "step " + std::to_string(f.step()) + "  rows " + std::to_string(f.u_x_size());
  if (f.u_x_size() > 0) {
    const auto [lo, hi] = std::minmax_element(f.u_x().begin(), f.u_x().end());
    const double mean = std::accumulate(f.u_x().begin(), f.u_x().end(), 0.0) / f.u_x_size();
    text += "  u_x min " + format("%.6g", *lo) + " mean " + format("%.6g", mean) + " max " + format("%.6g", *hi);
  }
  if (f.skipped_frames() > 0) text += "  skipped " + std::to_string(f.skipped_frames());
  return text;
}

std::string particle_frame_json(const lbsolid::v1::ParticleFrame& f) {
  std::vector<std::string> bodies;
  for (const auto& b : f.bodies())
    bodies.push_back(JsonObject()
                         .string("name", b.name())
                         .integer("particles", b.position_size() / 3)
                         .number("mass", b.mass())
                         .raw("centre_of_mass", vector_json(b.centre_of_mass()))
                         .raw("mean_velocity", vector_json(b.mean_velocity()))
                         .raw("angular_momentum", vector_json(b.angular_momentum()))
                         .raw("angular_velocity", vector_json(b.angular_velocity()))
                         .number("orientation", b.orientation())
                         .raw("orientation_quaternion", json_array(std::vector<double>{
                                                            b.orientation_quaternion().w(), b.orientation_quaternion().x(),
                                                            b.orientation_quaternion().y(), b.orientation_quaternion().z()}))
                         .raw("torque", vector_json(b.torque()))
                         .raw("position", json_array(std::vector<double>(b.position().begin(), b.position().end())))
                         .raw("velocity", json_array(std::vector<double>(b.velocity().begin(), b.velocity().end())))
                         .str());
  return JsonObject()
      .integer("step", f.step())
      .integer("skipped_frames", f.skipped_frames())
      .raw("bodies", json_array(bodies))
      .str();
}

std::string particle_frame_text(const lbsolid::v1::ParticleFrame& f) {
  std::string text = "step " + std::to_string(f.step());
  for (const auto& b : f.bodies())
    text += "  " + b.name() + ": com " + vector_text(b.centre_of_mass()) + " u " + vector_text(b.mean_velocity());
  if (f.skipped_frames() > 0) text += "  skipped " + std::to_string(f.skipped_frames());
  return text;
}

}  // namespace lbsolid::cli
