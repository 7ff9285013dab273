#pragma once
// Throwaway certificates for the TLS tests, made at test time with Debian's openssl command in a
// directory of the test's own: two unrelated CAs, a server certificate for localhost/127.0.0.1
// (valid, and one that expired), and client certificates (one signed by each CA).
#include <string>

namespace lbsolid::testing {

struct TestCertificates {
  std::string dir;
  std::string ca, other_ca;                  // PEM certificates of the two CAs
  std::string server_cert, server_key;       // by `ca`, valid for two days
  std::string expired_cert, expired_key;     // by `ca`, expired a day ago
  std::string renewed_cert, renewed_key;     // by `other_ca`, valid for two days (a renewal)
  std::string client_cert, client_key;       // by `ca`, CN `client_name`
  std::string stranger_cert, stranger_key;   // by `other_ca`, CN `client_name`
  std::string client_name = "carol";
};

// Throws std::runtime_error naming the openssl command that failed.
TestCertificates make_test_certificates(const std::string& dir);

// A file's whole contents (PEM files for gRPC's credentials).
std::string file_text(const std::string& path);

}  // namespace lbsolid::testing
