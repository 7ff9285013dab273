#pragma once
// Command-line parsing, kept free of RPC so it can be unit-tested:
//   lbsolid [--server HOST:PORT] [--timeout SECONDS] [--json] [--tls-ca FILE [--tls-cert FILE
//           --tls-key FILE]] [--token-file FILE] COMMAND [ARGS] [FLAGS]
// Global flags may also follow the command. Flags take their value as the next argument or after
// '='. Every problem is a UsageError (exit code 2) with a message naming the flag or argument.
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace lbsolid::cli {

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
  std::string command;  // the command named before the problem was found, if any
};

inline constexpr const char* kDefaultServer = "127.0.0.1:50051";
inline constexpr double kDefaultTimeoutSeconds = 30;

struct GlobalOptions {
  std::string server = kDefaultServer;  // --server, else $LBSOLID_SERVER, else the default
  double timeout_s = kDefaultTimeoutSeconds;  // deadline of each unary call
  bool json = false;
  std::string tls_ca;      // --tls-ca: TLS, trusting this CA (PEM)
  std::string tls_cert;    // --tls-cert, --tls-key: a client certificate for mutual TLS (PEM)
  std::string tls_key;
  std::string token_file;  // --token-file: a bearer token's file (else $LBSOLID_TOKEN)
  // Set when `server` is one address of a DNS name that named several daemons (daemon_names.h):
  // TLS checks the daemon's certificate for this name, not for the address.
  std::string server_name;
};

struct FlagSpec {
  std::string name;  // without the leading "--"
  bool takes_value = false;
  bool repeatable = false;  // may be given more than once (CommandLine::repeated keeps each value)
};

struct CommandSpec {
  std::string name;
  std::vector<std::string> positionals;  // argument names, all required
  std::vector<FlagSpec> flags;
  std::string synopsis;  // flags part of the usage line
  std::string summary;   // one line
};

const std::vector<CommandSpec>& command_specs();
const CommandSpec* find_command(std::string_view name);

struct CommandLine {
  GlobalOptions global;
  bool help = false;  // --help, -h or `help`: print usage (of `command` if one was given)
  bool version = false;  // --version: print the version and git revision
  std::string command;
  std::vector<std::string> positional;
  std::map<std::string, std::string> flags;  // given flags of the command; switches map to ""
  std::map<std::string, std::vector<std::string>> repeated;  // a repeatable flag's values, in order
  bool has(const std::string& flag) const { return flags.count(flag) != 0; }
  std::vector<std::string> all(const std::string& flag) const {
    const auto it = repeated.find(flag);
    return it == repeated.end() ? std::vector<std::string>{} : it->second;
  }
};

// args: argv[1..]; env_server: $LBSOLID_SERVER or null.
CommandLine parse_command_line(const std::vector<std::string>& args, const char* env_server);

// Strict number parsing for flag values: the whole text must be the number.
long parse_long(const std::string& flag, const std::string& text, long min_value);
double parse_seconds(const std::string& flag, const std::string& text);

std::string usage_text();                              // lbsolid --help
std::string command_usage(const CommandSpec& command);  // lbsolid COMMAND --help

// Typed options of the commands that have more than an id.
struct SubmitOptions {
  std::string file;
  long steps = 0;
  bool wait = false;        // also set by --out
  std::string out_dir;      // empty: no files
  std::string request_id;   // empty: the command makes a random one
  long profile_every = 1;   // default max(1, steps / 200)
  long particles_every = 1; // default max(1, steps / 200)
  std::vector<std::string> overrides;  // --set PATH=VALUE, applied in order (scenario_override.h)
};
SubmitOptions submit_options(const CommandLine& line);

struct RunOptions {
  std::string session_id;
  long steps = 0;
  bool wait = false;
};
RunOptions run_options(const CommandLine& line);

struct WatchOptions {
  enum class Stream { kProfiles, kParticles };
  std::string session_id;
  Stream stream = Stream::kProfiles;
  long every = 100;
  bool lossless = false;
  std::optional<long> frames;  // stop after this many frames
};
WatchOptions watch_options(const CommandLine& line);

}  // namespace lbsolid::cli
