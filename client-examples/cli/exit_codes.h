#pragma once
// The CLI's exit codes: what a script driving lbsolid may do next. Printed by `lbsolid --help`.
#include <grpcpp/support/status.h>

#include <string>

namespace lbsolid::cli {

enum ExitCode : int {
  kExitOk = 0,         // done / ok
  kExitRunFailed = 1,  // the run FAILED or was CANCELLED: do not retry
  kExitBadInput = 2,   // usage, unreadable file, or a request the daemon rejected: do not retry
  kExitTransient = 3,  // daemon unreachable or transient failure: retry
};

// The exit code for a failed RPC. Rejections of the request itself (INVALID_ARGUMENT, NOT_FOUND,
// ALREADY_EXISTS, FAILED_PRECONDITION, OUT_OF_RANGE, and UNIMPLEMENTED, PERMISSION_DENIED,
// UNAUTHENTICATED which a retry cannot fix either) are 2; everything that may pass on a retry
// (UNAVAILABLE, DEADLINE_EXCEEDED, RESOURCE_EXHAUSTED, ABORTED, INTERNAL, UNKNOWN, CANCELLED,
// DATA_LOSS) is 3. OK is 0.
ExitCode exit_code_for(grpc::StatusCode code);
// As above, with two permanent failures that arrive under transient codes: INTERNAL with no
// message (gRPC could not parse the request: the same bytes fail again) and RESOURCE_EXHAUSTED
// for a message over gRPC's size limit (the same call passes it again) are 2.
ExitCode exit_code_for(const grpc::Status& status);

// "NOT_FOUND" etc.
std::string status_code_name(grpc::StatusCode code);

// The block `lbsolid --help` prints about exit codes.
const char* exit_code_help();

}  // namespace lbsolid::cli
