#pragma once
// The connection to lbsolidd and the deadline every unary call carries (--timeout).
#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

#include "cli_error.h"
#include "cli_options.h"
#include "lbsolid/v1/simulation.grpc.pb.h"

namespace lbsolid::cli {

using Stub = lbsolid::v1::Simulation::Stub;

class Daemon {
 public:
  explicit Daemon(const GlobalOptions& options);
  Stub& stub() { return *stub_; }
  const GlobalOptions& options() const { return options_; }
  // Sets the per-call deadline (--timeout from now) on a unary call's or a bounded stream's context.
  void set_deadline(grpc::ClientContext& context) const;
  void set_deadline(grpc::ClientContext& context, double seconds) const;

  // One unary call with the deadline; throws RpcError on any status but OK.
  template <class Request, class Response>
  Response call(const char* rpc, grpc::Status (Stub::*method)(grpc::ClientContext*, const Request&, Response*),
                const Request& request) {
    return call(rpc, method, request, options_.timeout_s);
  }
  // The same with a deadline of its own, for a call whose work grows with the session's data.
  template <class Request, class Response>
  Response call(const char* rpc, grpc::Status (Stub::*method)(grpc::ClientContext*, const Request&, Response*),
                const Request& request, double seconds) {
    grpc::ClientContext context;
    set_deadline(context, seconds);
    Response response;
    const grpc::Status status = (stub_.get()->*method)(&context, request, &response);
    if (!status.ok()) throw RpcError(rpc, status);
    return response;
  }

 private:
  GlobalOptions options_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<Stub> stub_;
};

// A random 128-bit id as 32 lowercase hex digits, the default request id of submit and restore.
std::string random_request_id();

}  // namespace lbsolid::cli
