#include "cli_options.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <set>

#include "declared_steps.h"
#include "exit_codes.h"

namespace lbsolid::cli {
namespace {

const std::set<std::string>& global_value_flags() {
  static const std::set<std::string> flags = {"server", "timeout", "tls-ca", "tls-cert", "tls-key", "token-file"};
  return flags;
}

const FlagSpec* find_flag(const CommandSpec& command, const std::string& name) {
  for (const auto& flag : command.flags)
    if (flag.name == name) return &flag;
  return nullptr;
}

// Applies one global flag; returns false if `name` is not a global flag.
bool apply_global(GlobalOptions& global, bool& server_given, const std::string& name, const std::string& value) {
  if (name == "server") {
    if (value.empty()) throw UsageError("--server: expected HOST:PORT");
    global.server = value;
    server_given = true;
  } else if (name == "timeout") {
    global.timeout_s = parse_seconds("--timeout", value);
  } else if (name == "json") {
    global.json = true;
  } else if (name == "tls-ca" || name == "tls-cert" || name == "tls-key" || name == "token-file") {
    if (value.empty()) throw UsageError("--" + name + ": expected a file");
    std::string& field = name == "tls-ca"     ? global.tls_ca
                         : name == "tls-cert" ? global.tls_cert
                         : name == "tls-key"  ? global.tls_key
                                              : global.token_file;
    field = value;
  } else {
    return false;
  }
  return true;
}

}  // namespace

const std::vector<CommandSpec>& command_specs() {
  static const std::vector<CommandSpec> specs = {
      {"submit", {"FILE"},
       {{"steps", true}, {"wait", false}, {"out", true}, {"request-id", true}, {"profile-every", true},
        {"particles-every", true}, {"set", true, true}},
       "[--steps N] [--set PATH=VALUE]... [--wait] [--out DIR] [--request-id ID] [--profile-every N]\n"
       "      [--particles-every N]",
       "create a session from a scenario file (.textproto or .json) and run it N steps (default: the\n"
       "      N of the file's first '# steps: N' comment line)"},
      {"validate", {"FILE"}, {{"set", true, true}}, "[--set PATH=VALUE]...",
       "list every problem and warning the daemon finds in a scenario file (exit 2 if any problem)"},
      {"status", {"ID"}, {}, "", "show one session"},
      {"list", {}, {}, "", "list the daemon's sessions"},
      {"info", {}, {}, "", "show the daemon's version, capabilities and limits"},
      {"run", {"ID"}, {{"steps", true}, {"wait", false}}, "--steps N [--wait]", "run a session N more steps"},
      {"pause", {"ID"}, {}, "", "pause a running session"},
      {"resume", {"ID"}, {}, "", "resume a paused session"},
      {"cancel", {"ID"}, {}, "", "cancel a session (final)"},
      {"delete", {"ID"}, {}, "", "delete a session and its files"},
      {"checkpoint", {"ID"}, {}, "", "write a checkpoint; prints its id"},
      {"restore", {"CHECKPOINT_ID"}, {{"request-id", true}}, "[--request-id ID]",
       "create a PAUSED session from a checkpoint"},
      {"watch", {"ID"},
       {{"profiles", false}, {"particles", false}, {"every", true}, {"lossless", false}, {"frames", true}},
       "--profiles|--particles [--every N] [--lossless] [--frames K]",
       "print one line per frame of a session's profiles or particles"},
      {"fetch", {"ID"}, {{"out", true}, {"now", false}}, "--out DIR [--now]",
       "copy what the daemon recorded for the session and its checkpoints into DIR (--now: append the "
       "current density and velocity to DIR/fields.h5 instead)"},
  };
  return specs;
}

const CommandSpec* find_command(std::string_view name) {
  for (const auto& spec : command_specs())
    if (spec.name == name) return &spec;
  return nullptr;
}

long parse_long(const std::string& flag, const std::string& text, long min_value) {
  errno = 0;
  char* end = nullptr;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE)
    throw UsageError(flag + ": expected an integer, got '" + text + "'");
  if (value < min_value) throw UsageError(flag + ": must be at least " + std::to_string(min_value) + ", got " + text);
  return value;
}

double parse_seconds(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value) || value <= 0)
    throw UsageError(flag + ": expected a positive number of seconds, got '" + text + "'");
  return value;
}

namespace {

void parse_into(CommandLine& line, const std::vector<std::string>& args, const char* env_server) {
  bool server_given = false, only_positionals = false, help_command = false;
  const CommandSpec* command = nullptr;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (only_positionals || arg.size() < 2 || arg[0] != '-') {
      if (line.command.empty() && !help_command) {
        if (arg == "help") {
          help_command = line.help = true;
          continue;
        }
        command = find_command(arg);
        if (!command) throw UsageError("unknown command '" + arg + "'");
        line.command = arg;
      } else if (help_command && line.command.empty()) {
        command = find_command(arg);
        if (!command) throw UsageError("unknown command '" + arg + "'");
        line.command = arg;
      } else {
        line.positional.push_back(arg);
      }
      continue;
    }
    if (arg == "--") {
      only_positionals = true;
      continue;
    }
    if (arg == "-h" || arg == "--help") {
      line.help = true;
      continue;
    }
    if (arg == "--version") {
      line.version = true;
      continue;
    }
    if (arg.rfind("--", 0) != 0) throw UsageError("unknown option '" + arg + "'");
    std::string name = arg.substr(2), value;
    const auto equals = name.find('=');
    const bool inline_value = equals != std::string::npos;
    if (inline_value) {
      value = name.substr(equals + 1);
      name.resize(equals);
    }
    const bool global_value = global_value_flags().count(name) != 0;
    const FlagSpec* flag = command ? find_flag(*command, name) : nullptr;
    const bool takes_value = global_value || (flag && flag->takes_value);
    if (!global_value && name != "json" && !flag)
      throw UsageError(command ? "unknown option '--" + name + "' for " + command->name
                               : "unknown option '--" + name + "'");
    if (takes_value && !inline_value) {
      if (i + 1 >= args.size()) throw UsageError("--" + name + ": missing value");
      value = args[++i];
    } else if (!takes_value && inline_value) {
      throw UsageError("--" + name + " takes no value");
    }
    if (apply_global(line.global, server_given, name, value)) continue;
    if (flag && flag->repeatable) {
      line.repeated[name].push_back(value);
      line.flags[name] = value;
      continue;
    }
    if (line.flags.count(name)) throw UsageError("--" + name + " given twice");
    line.flags[name] = value;
  }
  if (!server_given && env_server && *env_server) line.global.server = env_server;
  if (line.help || line.version) return;
  if (!command) throw UsageError("no command given");
  if (line.positional.size() < command->positionals.size())
    throw UsageError(command->name + ": missing " + command->positionals[line.positional.size()]);
  if (line.positional.size() > command->positionals.size())
    throw UsageError(command->name + ": unexpected argument '" + line.positional[command->positionals.size()] + "'");
}

}  // namespace

CommandLine parse_command_line(const std::vector<std::string>& args, const char* env_server) {
  CommandLine line;
  try {
    parse_into(line, args, env_server);
  } catch (UsageError& e) {
    e.command = line.command;
    throw;
  }
  return line;
}

std::string command_usage(const CommandSpec& command) {
  std::string usage = "lbsolid [global options] " + command.name;
  for (const auto& arg : command.positionals) usage += " " + arg;
  if (!command.synopsis.empty()) usage += " " + command.synopsis;
  return usage + "\n  " + command.summary + "\n";
}

std::string usage_text() {
  std::string text =
      "lbsolid: command-line client of the lbsolidd simulation daemon\n\n"
      "Usage: lbsolid [--server HOST:PORT] [--timeout SECONDS] [--json] COMMAND [ARGS]\n\n"
      "Global options (also accepted after the command):\n"
      "  --server HOST:PORT  the daemon (default $LBSOLID_SERVER, else 127.0.0.1:50051); several,\n"
      "                      comma separated, or a DNS name of several addresses: submit picks\n"
      "                      the least loaded, every call about a session goes to the daemon\n"
      "                      that holds it\n"
      "  --timeout SECONDS   deadline of each call (default 30; listing outputs at least 300,\n"
      "                      downloads 3600); streams followed while waiting have none\n"
      "  --version           print the version and git revision\n"
      "  --json              print exactly one JSON object on stdout (one per line for watch),\n"
      "                      errors included as {\"error\": {...}}\n"
      "  --tls-ca FILE       TLS: trust the daemon's certificate if this CA (PEM) signed it\n"
      "  --tls-cert FILE, --tls-key FILE   a client certificate (mutual TLS)\n"
      "  --token-file FILE   send the token in FILE's first line (default $LBSOLID_TOKEN) as\n"
      "                      `authorization: Bearer <token>`\n"
      "  -h, --help          this text; `lbsolid COMMAND --help` for one command\n\n"
      "Commands:\n";
  for (const auto& command : command_specs()) {
    std::string head = "  " + command.name;
    for (const auto& arg : command.positionals) head += " " + arg;
    if (!command.synopsis.empty()) head += " " + command.synopsis;
    text += head + "\n      " + command.summary + "\n";
  }
  text +=
      "\nsubmit details:\n"
      "  --wait              follow the run to DONE, FAILED or CANCELLED (progress on stderr)\n"
      "  --out DIR           implies --wait; the daemon records the run (scenario.outputs, unless the\n"
      "                      file declares its own: particles and velocity profiles at the frame\n"
      "                      intervals, the final fields); then DIR/particles.h5 (H5MD), DIR/fields.h5\n"
      "                      + fields.xdmf are downloaded and checked, and DIR/status.json written\n"
      "                      (state, files with sizes and SHA-256, checksum). A retry with the same\n"
      "                      --request-id gets the same files; with other --steps it is refused\n"
      "  --request-id ID     makes a retried submit idempotent (default: a random 128-bit id)\n"
      "  --profile-every N, --particles-every N   frame interval in steps (default max(1, steps/200))\n"
      "  --set PATH=VALUE    (also for validate; repeatable) sets one scenario field, named as the\n"
      "                      daemon's errors name it: fluid.omega=1.2, bodies[0].load.x=2e-5; the\n"
      "                      scenario is then validated as the file would be\n"
      "watch details:\n"
      "  --every N (default 100)  --lossless: the run waits for this client  --frames K: stop after K\n\n";
  text += exit_code_help();
  return text;
}

SubmitOptions submit_options(const CommandLine& line) {
  SubmitOptions o;
  o.file = line.positional.at(0);
  if (line.has("steps")) {
    o.steps = parse_long("--steps", line.flags.at("steps"), 1);
  } else {
    o.steps = declared_steps(o.file);
    if (o.steps == 0) throw UsageError("submit: --steps N is required: " + o.file + " declares no '# steps: N' line");
  }
  o.out_dir = line.has("out") ? line.flags.at("out") : "";
  if (line.has("out") && o.out_dir.empty()) throw UsageError("--out: expected a directory");
  o.wait = line.has("wait") || !o.out_dir.empty();
  if (line.has("request-id")) {
    o.request_id = line.flags.at("request-id");
    if (o.request_id.empty()) throw UsageError("--request-id: must not be empty");
  }
  // About 200 frames per run: enough for a smooth u(t), small next to the run itself.
  const long every = std::max(1L, o.steps / 200);
  auto every_flag = [&](const std::string& name) {
    return line.has(name) ? parse_long("--" + name, line.flags.at(name), 1) : every;
  };
  o.profile_every = every_flag("profile-every");
  o.particles_every = every_flag("particles-every");
  o.overrides = line.all("set");
  return o;
}

RunOptions run_options(const CommandLine& line) {
  RunOptions o;
  o.session_id = line.positional.at(0);
  if (!line.has("steps")) throw UsageError("run: --steps N is required");
  o.steps = parse_long("--steps", line.flags.at("steps"), 1);
  o.wait = line.has("wait");
  return o;
}

WatchOptions watch_options(const CommandLine& line) {
  WatchOptions o;
  o.session_id = line.positional.at(0);
  if (line.has("profiles") == line.has("particles"))
    throw UsageError("watch: give exactly one of --profiles, --particles");
  o.stream = line.has("profiles") ? WatchOptions::Stream::kProfiles : WatchOptions::Stream::kParticles;
  if (line.has("every")) o.every = parse_long("--every", line.flags.at("every"), 1);
  o.lossless = line.has("lossless");
  if (line.has("frames")) o.frames = parse_long("--frames", line.flags.at("frames"), 1);
  return o;
}

}  // namespace lbsolid::cli
