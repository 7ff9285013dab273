#pragma once
// The daemon's recorded outputs of a session (ListOutputs, DownloadOutput) copied into a
// directory: each file is downloaded into "<dir>/.<name>.part-<pid>", resumed from the bytes
// received if the stream breaks (naming the version, so a file that changed is fetched afresh),
// checked against the SHA-256 the daemon named, and renamed over <dir>/<name>. A copy that is
// already there with that SHA-256 is kept, so a retried command rewrites nothing.
#include <string>
#include <vector>

#include "result_writer.h"
#include "rpc_client.h"

namespace lbsolid::cli {

// Creates DIR if needed and checks it can be written: called before the session is created, so a
// bad --out fails without leaving a session behind. Throws CliError (exit 2).
void prepare_output_directory(const std::string& dir);

// The files listed for the session whose name passes `wanted` ("checkpoints/..." included if it
// says so). Throws RpcError, or CliError (exit 2: cannot write; exit 3: the copy does not match).
std::vector<FileEntry> download_outputs(Daemon& daemon, const std::string& session_id, const std::string& dir,
                                        bool with_checkpoints);

}  // namespace lbsolid::cli
