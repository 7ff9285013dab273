#include "channel_security.h"

#include <grpcpp/support/client_interceptor.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace lbsolid::cli {
namespace {

std::string read_file(const std::string& flag, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError(flag + ": cannot read " + path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The token file's first line, without surrounding white space.
std::string token_of(const GlobalOptions& options) {
  std::string token;
  if (!options.token_file.empty()) {
    std::istringstream lines(read_file("--token-file", options.token_file));
    std::getline(lines, token);
  } else if (const char* env = std::getenv("LBSOLID_TOKEN")) {
    token = env;
  }
  const auto first = token.find_first_not_of(" \t\r");
  const auto last = token.find_last_not_of(" \t\r");
  token = first == std::string::npos ? "" : token.substr(first, last - first + 1);
  if (!options.token_file.empty() && token.empty()) throw UsageError("--token-file: " + options.token_file + " is empty");
  return token;
}

class BearerToken final : public grpc::experimental::Interceptor {
 public:
  explicit BearerToken(const std::string& header) : header_(header) {}
  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(grpc::experimental::InterceptionHookPoints::PRE_SEND_INITIAL_METADATA))
      methods->GetSendInitialMetadata()->insert({"authorization", header_});
    methods->Proceed();
  }

 private:
  const std::string& header_;
};

class BearerTokenFactory final : public grpc::experimental::ClientInterceptorFactoryInterface {
 public:
  explicit BearerTokenFactory(std::string token) : header_("Bearer " + std::move(token)) {}
  grpc::experimental::Interceptor* CreateClientInterceptor(grpc::experimental::ClientRpcInfo*) override {
    return new BearerToken(header_);  // gRPC owns it; the factory outlives the channel's calls
  }

 private:
  const std::string header_;
};

}  // namespace

std::shared_ptr<grpc::Channel> open_channel(const GlobalOptions& options, const grpc::ChannelArguments& args) {
  if (options.tls_cert.empty() != options.tls_key.empty())
    throw UsageError("--tls-cert, --tls-key: give both or neither");
  if (!options.tls_cert.empty() && options.tls_ca.empty())
    throw UsageError("--tls-cert: needs --tls-ca (a client certificate is sent over TLS)");
  std::shared_ptr<grpc::ChannelCredentials> credentials = grpc::InsecureChannelCredentials();
  if (!options.tls_ca.empty()) {
    grpc::SslCredentialsOptions ssl;
    ssl.pem_root_certs = read_file("--tls-ca", options.tls_ca);
    if (!options.tls_cert.empty()) {
      ssl.pem_cert_chain = read_file("--tls-cert", options.tls_cert);
      ssl.pem_private_key = read_file("--tls-key", options.tls_key);
    }
    credentials = grpc::SslCredentials(ssl);
  }
  grpc::ChannelArguments with_name = args;
  // An address resolved from a name: the certificate must bear the name.
  if (!options.server_name.empty() && !options.tls_ca.empty()) with_name.SetSslTargetNameOverride(options.server_name);
  const std::string token = token_of(options);
  if (token.empty()) return grpc::CreateCustomChannel(options.server, credentials, with_name);
  std::vector<std::unique_ptr<grpc::experimental::ClientInterceptorFactoryInterface>> interceptors;
  interceptors.push_back(std::make_unique<BearerTokenFactory>(token));
  return grpc::experimental::CreateCustomChannelWithInterceptors(options.server, credentials, with_name,
                                                                 std::move(interceptors));
}

}  // namespace lbsolid::cli
