#pragma once
// The errors a command throws to main(), each carrying the exit code it ends the CLI with.
#include <grpcpp/support/status.h>

#include <stdexcept>
#include <string>

#include "exit_codes.h"
#include "result_writer.h"

namespace lbsolid::cli {

// A failure with a known exit code: an unreadable file (2), a local write failure (2), ...
struct CliError : std::runtime_error {
  CliError(ExitCode code, const std::string& message) : std::runtime_error(message), exit_code(code) {}
  ExitCode exit_code;
};

// A failed RPC: "<rpc>: <CODE>: <the daemon's message>".
struct RpcError : std::runtime_error {
  RpcError(const std::string& rpc, const grpc::Status& status);
  std::string rpc;
  grpc::StatusCode code;
  std::string detail;  // the status message alone
  ExitCode exit_code() const { return exit_code_for(grpc::Status(code, detail)); }
};

// What a failure is in the JSON result: an RpcError its gRPC code and call, a UsageError USAGE, a
// CliError BAD_INPUT or TRANSIENT by its exit code, anything else INTERNAL (exit 3).
ResultError result_error(const std::exception& e);

}  // namespace lbsolid::cli
