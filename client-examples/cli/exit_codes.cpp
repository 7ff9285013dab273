#include "exit_codes.h"

namespace lbsolid::cli {

ExitCode exit_code_for(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK:
      return kExitOk;
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::NOT_FOUND:
    case grpc::StatusCode::ALREADY_EXISTS:
    case grpc::StatusCode::FAILED_PRECONDITION:
    case grpc::StatusCode::OUT_OF_RANGE:
    case grpc::StatusCode::UNIMPLEMENTED:  // version skew: the same daemon will say it again
    case grpc::StatusCode::PERMISSION_DENIED:
    case grpc::StatusCode::UNAUTHENTICATED:
    case grpc::StatusCode::DATA_LOSS:  // an unreadable checkpoint stays unreadable
      return kExitBadInput;
    case grpc::StatusCode::UNAVAILABLE:
    case grpc::StatusCode::DEADLINE_EXCEEDED:
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
    case grpc::StatusCode::ABORTED:
    case grpc::StatusCode::INTERNAL:
    case grpc::StatusCode::UNKNOWN:
    case grpc::StatusCode::CANCELLED:  // e.g. the daemon shutting down mid-call
    default:
      return kExitTransient;
  }
}

ExitCode exit_code_for(const grpc::Status& status) {
  const std::string& message = status.error_message();
  if (status.error_code() == grpc::StatusCode::INTERNAL && message.empty()) return kExitBadInput;
  if (status.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED &&
      (message.find("message larger than max") != std::string::npos ||
       message.find("metadata size") != std::string::npos))
    return kExitBadInput;
  return exit_code_for(status.error_code());
}

std::string status_code_name(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK: return "OK";
    case grpc::StatusCode::CANCELLED: return "CANCELLED";
    case grpc::StatusCode::UNKNOWN: return "UNKNOWN";
    case grpc::StatusCode::INVALID_ARGUMENT: return "INVALID_ARGUMENT";
    case grpc::StatusCode::DEADLINE_EXCEEDED: return "DEADLINE_EXCEEDED";
    case grpc::StatusCode::NOT_FOUND: return "NOT_FOUND";
    case grpc::StatusCode::ALREADY_EXISTS: return "ALREADY_EXISTS";
    case grpc::StatusCode::PERMISSION_DENIED: return "PERMISSION_DENIED";
    case grpc::StatusCode::RESOURCE_EXHAUSTED: return "RESOURCE_EXHAUSTED";
    case grpc::StatusCode::FAILED_PRECONDITION: return "FAILED_PRECONDITION";
    case grpc::StatusCode::ABORTED: return "ABORTED";
    case grpc::StatusCode::OUT_OF_RANGE: return "OUT_OF_RANGE";
    case grpc::StatusCode::UNIMPLEMENTED: return "UNIMPLEMENTED";
    case grpc::StatusCode::INTERNAL: return "INTERNAL";
    case grpc::StatusCode::UNAVAILABLE: return "UNAVAILABLE";
    case grpc::StatusCode::DATA_LOSS: return "DATA_LOSS";
    case grpc::StatusCode::UNAUTHENTICATED: return "UNAUTHENTICATED";
    default: return "STATUS_" + std::to_string(static_cast<int>(code));
  }
}

const char* exit_code_help() {
  return "Exit codes:\n"
         "  0  done / ok\n"
         "  1  the run FAILED or was CANCELLED (commands that wait: submit --wait/--out, run --wait);\n"
         "     do not retry\n"
         "  2  bad input: usage error, unreadable or invalid scenario file, or the daemon rejected the\n"
         "     request (INVALID_ARGUMENT, NOT_FOUND, ALREADY_EXISTS, FAILED_PRECONDITION, OUT_OF_RANGE,\n"
         "     UNIMPLEMENTED, PERMISSION_DENIED, UNAUTHENTICATED, DATA_LOSS, INTERNAL with no message:\n"
         "     a request gRPC could not parse, RESOURCE_EXHAUSTED for a message over gRPC's size limit);\n"
         "     do not retry\n"
         "  3  daemon unreachable or transient failure (UNAVAILABLE, DEADLINE_EXCEEDED,\n"
         "     RESOURCE_EXHAUSTED, ABORTED, INTERNAL, UNKNOWN, CANCELLED); retry\n"
         "     (submit is idempotent when retried with the same --request-id)\n";
}

}  // namespace lbsolid::cli
