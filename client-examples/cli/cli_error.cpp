#include "cli_error.h"

#include "cli_options.h"

namespace lbsolid::cli {

RpcError::RpcError(const std::string& rpc_name, const grpc::Status& status)
    : std::runtime_error(rpc_name + ": " + status_code_name(status.error_code()) + ": " +
                         (status.error_message().empty() ? "(no message)" : status.error_message())),
      rpc(rpc_name),
      code(status.error_code()),
      detail(status.error_message()) {}

ResultError result_error(const std::exception& e) {
  if (const auto* rpc = dynamic_cast<const RpcError*>(&e))
    return {status_code_name(rpc->code), rpc->rpc, e.what(), rpc->exit_code()};
  if (dynamic_cast<const UsageError*>(&e)) return {"USAGE", "", e.what(), kExitBadInput};
  if (const auto* cli = dynamic_cast<const CliError*>(&e))
    return {cli->exit_code == kExitBadInput ? "BAD_INPUT" : "TRANSIENT", "", e.what(), cli->exit_code};
  return {"INTERNAL", "", e.what(), kExitTransient};
}

}  // namespace lbsolid::cli
