// fetch: what the daemon recorded for the session (scenario.outputs) and its checkpoints, copied
// into DIR (output_download.h); with --now, the session's current density and velocity appended
// as a snapshot to DIR/fields.h5 (and DIR/fields.xdmf for ParaView) instead.
#include <filesystem>

#include "commands.h"
#include "daemon_placement.h"
#include "field_fetch.h"
#include "json_writer.h"
#include "output_download.h"
#include "rpc_client.h"
#include "io/storage/field_snapshot.h"

namespace lbsolid::cli {

int cmd_fetch(const CommandLine& line) {
  const std::string session_id = line.positional.at(0);
  if (!line.has("out") || line.flags.at("out").empty()) throw UsageError("fetch: --out DIR is required");
  const std::filesystem::path dir = line.flags.at("out");
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) throw CliError(kExitBadInput, dir.string() + ": " + error.message());

  Daemon daemon(daemon_of_session(line.global, session_id));
  CommandResult result;
  result.command = line.command;
  result.session_id = session_id;
  result.wrote_files = true;
  if (!line.has("now")) {
    result.files = download_outputs(daemon, session_id, dir.string(), /*with_checkpoints=*/true);
    std::string text =
        result.files.empty() ? session_id + ": nothing recorded (scenario.outputs) and no checkpoints" : "";
    for (const auto& f : result.files)
      text += (text.empty() ? "" : "\n") + ("wrote " + (dir / f.name).string() + " (" + std::to_string(f.bytes) + " bytes)");
    emit(line, result, text);
    return kExitOk;
  }
  const FetchedFields fetched = fetch_fields(daemon, session_id);
  const std::string h5 = (dir / "fields.h5").string();
  write_field_snapshot(h5, fetched);
  const std::string xdmf = lbsolid::server::storage::xdmf_path_for(h5);
  const auto& shape = fetched.fields.shape;
  result.step = fetched.step;
  result.files = describe_files(dir.string(), {"fields.h5", std::filesystem::path(xdmf).filename().string()});
  result.add("fields", JsonObject()
                           .integer("step", fetched.step)
                           .raw("shape", json_array(std::vector<double>{double(shape[2]), double(shape[1]),
                                                                        double(shape[0])}))
                           .string("file", h5)
                           .string("xdmf", xdmf)
                           .str());
  emit(line, result,
       session_id + " step " + std::to_string(fetched.step) + ": appended density and velocity (" +
           std::to_string(shape[0]) + " x " + std::to_string(shape[1]) + " x " + std::to_string(shape[2]) + ") to " +
           h5 + " (" + xdmf + ")");
  return kExitOk;
}

}  // namespace lbsolid::cli
