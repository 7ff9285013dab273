#include "server/auth/transport.h"

#include <grpcpp/security/auth_metadata_processor.h>
#include <grpcpp/security/tls_certificate_provider.h>
#include <grpcpp/security/tls_credentials_options.h>

#include <atomic>
#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"

namespace lbsolid::server::auth {

namespace {

absl::StatusOr<std::string> read_pem(const std::string& flag, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::InvalidArgumentError(absl::StrCat("--", flag, ": cannot read ", path));
  std::ostringstream text;
  text << in.rdbuf();
  if (text.str().find("-----BEGIN ") == std::string::npos)
    return absl::InvalidArgumentError(absl::StrCat("--", flag, ": ", path, " holds no PEM block"));
  return text.str();
}

// Runs inside gRPC before the call is dispatched: a call it refuses never reaches a session.
class TokenProcessor final : public grpc::AuthMetadataProcessor {
 public:
  explicit TokenProcessor(std::shared_ptr<const Authenticator> authenticator)
      : authenticator_(std::move(authenticator)) {
    published_.store(true, std::memory_order_release);
  }

  bool IsBlocking() const override { return false; }  // a map lookup: no need for another thread

  grpc::Status Process(const InputMetadata& metadata, grpc::AuthContext* context, OutputMetadata* consumed,
                       OutputMetadata*) override {
    (void)published_.load(std::memory_order_acquire);  // orders this call after the constructor (below)
    const auto path = metadata.find(":path");
    if (path != metadata.end() && probe_path(std::string_view(path->second.data(), path->second.size())))
      return grpc::Status::OK;
    std::optional<std::string_view> authorization;
    const auto header = metadata.find("authorization");
    if (header != metadata.end()) authorization = std::string_view(header->second.data(), header->second.size());
    std::string certificate_name;
    for (const auto& name : context->FindPropertyValues(GRPC_X509_CN_PROPERTY_NAME))
      certificate_name.assign(name.data(), name.size());
    const auto identity = authenticator_->identify(authorization, certificate_name);
    if (!identity.ok()) return grpc::Status(grpc::StatusCode::UNAUTHENTICATED, std::string(identity.status().message()));
    context->AddProperty(kOwnerProperty, identity->owner);
    context->AddProperty(kRoleProperty, identity->role == Role::kAdmin ? "admin" : "user");
    if (authorization) consumed->insert({"authorization", std::string(*authorization)});
    return grpc::Status::OK;
  }

 private:
  // Probes and tools reach these without credentials: they reveal no session.
  static bool probe_path(std::string_view path) {
    return path.starts_with("/grpc.health.v1.Health/") || path.starts_with("/grpc.reflection.");
  }
  std::shared_ptr<const Authenticator> authenticator_;
  // gRPC's threads start before this processor is made (lbsolidd initialises gRPC first, below
  // the simulation's priority) and are handed it through gRPC's own locks, which ThreadSanitizer
  // cannot see (a race reported on authenticator_ and the token table in one CI run of a4adfeb).
  // This release in the constructor and acquire in Process() order every call after everything
  // the daemon built before it: the authenticator and its token table.
  std::atomic<bool> published_{false};
};

}  // namespace

bool is_local_address(const std::string& listen) {
  if (listen.starts_with("unix:") || listen.starts_with("unix-abstract:")) return true;
  std::string host = listen.substr(0, listen.rfind(':'));
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  return host == "localhost" || host == "::1" || host.starts_with("127.");
}

absl::Status check_advertise_address(const std::string& address) {
  const auto refuse = [](const std::string& why) {
    return absl::InvalidArgumentError("--advertise_address: " + why);
  };
  if (address.empty()) return absl::OkStatus();
  if (address.size() > 255) return refuse("longer than 255 characters");
  for (const char c : address)
    if (c <= ' ' || c > '~') return refuse("only printable characters without spaces");
  if (address.starts_with("unix:")) {
    return address.size() > 5 ? absl::OkStatus() : refuse("unix: needs a path");
  }
  const std::size_t colon = address.rfind(':');
  if (colon == std::string::npos || colon == 0) return refuse("'" + address + "' is not HOST:PORT or unix:PATH");
  const std::string port = address.substr(colon + 1);
  if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos ||
      std::stol(port) < 1 || std::stol(port) > 65535)
    return refuse("the port of '" + address + "' must be a number in [1, 65535]");
  return absl::OkStatus();
}

absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> server_credentials(
    const TransportOptions& options, std::shared_ptr<const Authenticator> authenticator) {
  if (options.tls_cert.empty() != options.tls_key.empty())
    return absl::InvalidArgumentError("--tls_cert, --tls_key: give both or neither");
  // Off loopback, every caller of a daemon that authenticates nobody would be its admin.
  if (!is_local_address(options.listen) && !authenticator->authenticates() && !options.allow_insecure)
    return absl::InvalidArgumentError(absl::StrCat(
        "--listen: ", options.listen,
        " is not loopback or a Unix socket: give --tokens_file or --tls_client_ca so that callers are "
        "authenticated, or --allow_insecure to let anyone who reaches the port act as admin"));
  if (options.tls_cert.empty()) {
    if (!options.tls_client_ca.empty())
      return absl::InvalidArgumentError("--tls_client_ca: needs --tls_cert and --tls_key (mutual TLS is TLS)");
    if (!is_local_address(options.listen) && !options.allow_insecure)
      return absl::InvalidArgumentError(absl::StrCat(
          "--listen: ", options.listen,
          " is not loopback or a Unix socket: give --tls_cert and --tls_key, or --allow_insecure to serve plaintext "
          "anyway (anyone on the network can then read and forge calls)"));
    return grpc::InsecureServerCredentials();
  }
  // Read once here so that a missing or wrong file stops the start with its name; the daemon then
  // serves what the files hold, read again every reload interval (a renewed certificate needs no
  // restart; a file that cannot be read keeps the one in force).
  for (const auto& [flag, path] : {std::pair{"tls_cert", options.tls_cert}, std::pair{"tls_key", options.tls_key},
                                   std::pair{"tls_client_ca", options.tls_client_ca}})
    if (!path.empty())
      if (const auto pem = read_pem(flag, path); !pem.ok()) return pem.status();
  if (options.reload_interval_s < 1) return absl::InvalidArgumentError("--tls_reload_interval: at least 1s");
  // Process() is ordered after this (TokenProcessor::published_).
  auto processor = std::make_shared<TokenProcessor>(std::move(authenticator));
  const auto files = options.tls_client_ca.empty()
                         ? std::make_shared<grpc::experimental::FileWatcherCertificateProvider>(
                               options.tls_key, options.tls_cert, options.reload_interval_s)
                         : std::make_shared<grpc::experimental::FileWatcherCertificateProvider>(
                               options.tls_key, options.tls_cert, options.tls_client_ca, options.reload_interval_s);
  grpc::experimental::TlsServerCredentialsOptions tls(files);
  tls.watch_identity_key_cert_pairs();
  if (!options.tls_client_ca.empty()) {
    tls.watch_root_certs();
    tls.set_cert_request_type(GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY);
  }
  auto credentials = grpc::experimental::TlsServerCredentials(tls);
  credentials->SetAuthMetadataProcessor(std::move(processor));
  return credentials;
}

}  // namespace lbsolid::server::auth
