#include "service/test_certificates.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace lbsolid::testing {

namespace {

void openssl(const std::string& dir, const std::string& arguments) {
  const std::string command = "cd '" + dir + "' && openssl " + arguments + " >openssl.log 2>&1";
  if (std::system(command.c_str()) != 0)
    throw std::runtime_error("openssl " + arguments + " failed: " + file_text(dir + "/openssl.log"));
}

// A key and a certificate signing request for `subject`, then the certificate signed by `ca`
// valid for `days` (negative: it expired that long ago).
void signed_certificate(const std::string& dir, const std::string& name, const std::string& subject,
                        const std::string& ca, int days) {
  openssl(dir, "req -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -keyout " + name + ".key -out " + name +
                   ".csr -subj '" + subject + "'");
  openssl(dir, "x509 -req -in " + name + ".csr -CA " + ca + ".pem -CAkey " + ca + ".key -CAcreateserial -out " +
                   name + ".pem -days " + std::to_string(days) + " -extfile san.cnf");
}

}  // namespace

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TestCertificates make_test_certificates(const std::string& dir) {
  TestCertificates c;
  c.dir = dir;
  std::ofstream(dir + "/san.cnf") << "subjectAltName=DNS:localhost,IP:127.0.0.1\n";
  for (const std::string ca : {"ca", "other_ca"})
    openssl(dir, "req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -keyout " + ca + ".key -out " +
                     ca + ".pem -days 2 -subj '/CN=lbsolid test " + ca + "'");
  signed_certificate(dir, "server", "/CN=localhost", "ca", 2);
  signed_certificate(dir, "expired", "/CN=localhost", "ca", -1);
  signed_certificate(dir, "renewed", "/CN=localhost", "other_ca", 2);
  signed_certificate(dir, "client", "/CN=" + c.client_name, "ca", 2);
  signed_certificate(dir, "stranger", "/CN=" + c.client_name, "other_ca", 2);
  const auto path = [&](const std::string& file) { return dir + "/" + file; };
  c.ca = path("ca.pem");
  c.other_ca = path("other_ca.pem");
  c.server_cert = path("server.pem");
  c.server_key = path("server.key");
  c.expired_cert = path("expired.pem");
  c.expired_key = path("expired.key");
  c.renewed_cert = path("renewed.pem");
  c.renewed_key = path("renewed.key");
  c.client_cert = path("client.pem");
  c.client_key = path("client.key");
  c.stranger_cert = path("stranger.pem");
  c.stranger_key = path("stranger.key");
  return c;
}

}  // namespace lbsolid::testing
