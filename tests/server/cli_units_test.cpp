// Unit tests of the lbsolid CLI's pure pieces: SHA-256 against the FIPS 180-2 vectors, the
// --json result schema and status.json checksum, option parsing and its usage errors, the exit-code mapping, JSON text and
// the progress line. The commands themselves need a daemon and are tested end to end elsewhere.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_error.h"
#include "cli_options.h"
#include "daemon_names.h"
#include "declared_steps.h"
#include "exit_codes.h"
#include "json_writer.h"
#include "progress_bar.h"
#include "result_writer.h"
#include "io/storage/sha256.h"

namespace lbsolid::cli {
namespace {

// The CLI's checksums are storage's SHA-256 (one implementation, lbsolid_sha256).
using server::storage::Sha256;
using server::storage::sha256_file_hex;
using server::storage::sha256_hex;

// --- SHA-256 -------------------------------------------------------------------------------------

TEST(Sha256, FipsVectors) {
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  // The two-block vector of FIPS 180-2: padding spills into a second block.
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(Sha256, MillionAsInPiecesOfAnySize) {
  // FIPS 180-2's third vector, fed in uneven pieces to exercise the block buffer.
  Sha256 hash;
  const std::string piece(997, 'a');
  std::size_t fed = 0;
  while (fed + piece.size() <= 1000000) {
    hash.update(piece);
    fed += piece.size();
  }
  hash.update(std::string(1000000 - fed, 'a'));
  EXPECT_EQ(hash.hex_digest(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, PaddingBoundaries) {
  // 55, 56 and 64 bytes: the length field just fits, just does not, and a full block.
  EXPECT_EQ(sha256_hex(std::string(55, 'a')), "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318");
  EXPECT_EQ(sha256_hex(std::string(56, 'a')), "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a");
  EXPECT_EQ(sha256_hex(std::string(64, 'a')), "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb");
}

TEST(Sha256, FileMatchesString) {
  const auto path = std::filesystem::temp_directory_path() / "lbsolid_cli_sha256_test.bin";
  std::ofstream(path, std::ios::binary) << "abc";
  EXPECT_EQ(sha256_file_hex(path.string()), sha256_hex("abc"));
  std::filesystem::remove(path);
  EXPECT_THROW(sha256_file_hex(path.string()), std::runtime_error);
}

// --- status.json -------------------------------------------------------------------------------

TEST(ResultWriter, ChecksumIsOverHexStringsInNameOrder) {
  const std::vector<FileEntry> files = {{"b.h5", 3, sha256_hex("b")}, {"a.h5", 2, sha256_hex("a")}};
  EXPECT_EQ(combined_checksum(files), sha256_hex(sha256_hex("a") + sha256_hex("b")));
  EXPECT_EQ(combined_checksum({}), sha256_hex(""));
}

// The schema's keys in their documented order, every one present: a session's result with files
// and an error, and a result with nothing but its command (nulls).
TEST(ResultWriter, ResultJsonHasEveryKeyOfTheSchema) {
  CommandResult r;
  r.command = "submit";
  r.session_id = "s-000001";
  r.state = "FAILED";
  r.step = 120;
  r.target_step = 200;
  r.message = "step 120: \"rho\" < 0";
  r.files = {{"particles.h5", 10, sha256_hex("x")}};
  r.wrote_files = true;
  r.error = ResultError{"UNAVAILABLE", "DownloadOutput", "DownloadOutput: UNAVAILABLE: gone", 3};
  r.exit_code = 3;
  r.add("deleted", "true");
  EXPECT_EQ(result_json(r),
            "{\"version\":3,\"command\":\"submit\",\"session_id\":\"s-000001\",\"state\":\"FAILED\",\"step\":120,"
            "\"target_step\":200,\"message\":\"step 120: \\\"rho\\\" < 0\",\"files\":[{\"name\":\"particles.h5\","
            "\"bytes\":10,\"sha256\":\"" + sha256_hex("x") + "\"}],\"checksum\":\"" + sha256_hex(sha256_hex("x")) +
            "\",\"error\":{\"code\":\"UNAVAILABLE\",\"rpc\":\"DownloadOutput\",\"message\":\"DownloadOutput: "
            "UNAVAILABLE: gone\",\"exit_code\":3},\"exit_code\":3,\"deleted\":true}");

  CommandResult bare;
  bare.command = "list";
  bare.error = ResultError{"USAGE", "", "list: unexpected argument 'x'", 2};
  bare.exit_code = 2;
  EXPECT_EQ(result_json(bare),
            "{\"version\":3,\"command\":\"list\",\"session_id\":null,\"state\":null,\"step\":null,"
            "\"target_step\":null,\"message\":null,\"files\":[],\"checksum\":null,\"error\":{\"code\":\"USAGE\","
            "\"rpc\":null,\"message\":\"list: unexpected argument 'x'\",\"exit_code\":2},\"exit_code\":2}");
}

// Each kind of failure a command throws becomes the error object its exit code documents.
TEST(ResultWriter, FailuresBecomeErrorsWithTheirCodes) {
  const ResultError rpc = result_error(RpcError("GetSession", grpc::Status(grpc::StatusCode::NOT_FOUND, "no s-1")));
  EXPECT_EQ(rpc.code, "NOT_FOUND");
  EXPECT_EQ(rpc.rpc, "GetSession");
  EXPECT_EQ(rpc.message, "GetSession: NOT_FOUND: no s-1");
  EXPECT_EQ(rpc.exit_code, 2);
  EXPECT_EQ(result_error(RpcError("Step", grpc::Status(grpc::StatusCode::UNAVAILABLE, "x"))).exit_code, 3);
  EXPECT_EQ(result_error(UsageError("--steps: missing")).code, "USAGE");
  const ResultError bad = result_error(CliError(kExitBadInput, "f: unreadable"));
  EXPECT_EQ(bad.code, "BAD_INPUT");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(result_error(CliError(kExitTransient, "copy differs")).code, "TRANSIENT");
  const ResultError other = result_error(std::runtime_error("bad_alloc"));
  EXPECT_EQ(other.code, "INTERNAL");
  EXPECT_EQ(other.exit_code, 3);
}

TEST(ResultWriter, AtomicWriteAndFileDescriptions) {
  const std::string json = "{\"version\":3}";
  const auto dir = std::filesystem::temp_directory_path() / "lbsolid_cli_units_status";
  std::filesystem::create_directories(dir);
  const auto path = dir / "status.json";
  write_file_atomically(path.string(), json);
  std::ifstream in(path);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), json);
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  const auto described = describe_files(dir.string(), {"status.json", "missing.h5"});
  ASSERT_EQ(described.size(), 1u);
  EXPECT_EQ(described[0].bytes, json.size());
  EXPECT_EQ(described[0].sha256, sha256_hex(json));
  std::filesystem::remove_all(dir);
}

// --- options -------------------------------------------------------------------------------------

CommandLine parse(const std::vector<std::string>& args, const char* env = nullptr) {
  return parse_command_line(args, env);
}

TEST(CliOptions, GlobalDefaultsAndEnvironment) {
  auto line = parse({"list"});
  EXPECT_EQ(line.global.server, "127.0.0.1:50051");
  EXPECT_DOUBLE_EQ(line.global.timeout_s, 30);
  EXPECT_FALSE(line.global.json);
  EXPECT_EQ(parse({"list"}, "daemon:7000").global.server, "daemon:7000");
  // --server wins over the environment, before or after the command, with or without '='.
  EXPECT_EQ(parse({"--server", "a:1", "list"}, "daemon:7000").global.server, "a:1");
  line = parse({"list", "--server=b:2", "--timeout", "2.5", "--json"}, "daemon:7000");
  EXPECT_EQ(line.global.server, "b:2");
  EXPECT_DOUBLE_EQ(line.global.timeout_s, 2.5);
  EXPECT_TRUE(line.global.json);
}

TEST(CliOptions, SubmitDefaultsAndFlags) {
  auto o = submit_options(parse({"submit", "fig5.textproto", "--steps", "15000"}));
  EXPECT_EQ(o.file, "fig5.textproto");
  EXPECT_EQ(o.steps, 15000);
  EXPECT_FALSE(o.wait);
  EXPECT_TRUE(o.request_id.empty());
  EXPECT_EQ(o.profile_every, 75);  // max(1, N/200)
  EXPECT_EQ(o.particles_every, 75);
  EXPECT_EQ(submit_options(parse({"submit", "f", "--steps", "50"})).particles_every, 1);

  o = submit_options(parse({"--json", "submit", "f", "--steps=10", "--out", "dir", "--request-id", "r1",
                            "--profile-every", "3", "--particles-every=4"}));
  EXPECT_TRUE(o.wait);  // --out implies --wait
  EXPECT_EQ(o.out_dir, "dir");
  EXPECT_EQ(o.request_id, "r1");
  EXPECT_EQ(o.profile_every, 3);
  EXPECT_EQ(o.particles_every, 4);
}

TEST(CliOptions, OtherCommands) {
  auto r = run_options(parse({"run", "s-000001", "--steps", "100", "--wait"}));
  EXPECT_EQ(r.session_id, "s-000001");
  EXPECT_EQ(r.steps, 100);
  EXPECT_TRUE(r.wait);
  auto w = watch_options(parse({"watch", "s-1", "--particles", "--frames", "3", "--lossless"}));
  EXPECT_EQ(w.stream, WatchOptions::Stream::kParticles);
  EXPECT_EQ(w.every, 100);
  EXPECT_TRUE(w.lossless);
  ASSERT_TRUE(w.frames.has_value());
  EXPECT_EQ(*w.frames, 3);
  w = watch_options(parse({"watch", "s-1", "--profiles", "--every", "7"}));
  EXPECT_EQ(w.stream, WatchOptions::Stream::kProfiles);
  EXPECT_EQ(w.every, 7);
  EXPECT_FALSE(w.frames.has_value());
  EXPECT_EQ(parse({"restore", "s-1/step-000000100", "--request-id", "x"}).flags.at("request-id"), "x");
  EXPECT_EQ(parse({"fetch", "s-1", "--out", "d"}).flags.at("out"), "d");
}

TEST(CliOptions, Version) {
  EXPECT_TRUE(parse({"--version"}).version);
  EXPECT_TRUE(parse({"--server", "h:1", "--version"}).version);
  EXPECT_FALSE(parse({"list"}).version);
}

TEST(CliOptions, Help) {
  EXPECT_TRUE(parse({"--help"}).help);
  EXPECT_TRUE(parse({"-h"}).help);
  auto line = parse({"help", "submit"});
  EXPECT_TRUE(line.help);
  EXPECT_EQ(line.command, "submit");
  line = parse({"watch", "--help"});  // no positional needed with --help
  EXPECT_TRUE(line.help);
  EXPECT_EQ(line.command, "watch");
  const std::string usage = usage_text();
  for (const char* word : {"submit", "checkpoint", "restore", "watch", "fetch", "Exit codes", "UNAVAILABLE"})
    EXPECT_NE(usage.find(word), std::string::npos) << word;
}

TEST(CliOptions, UsageErrors) {
  const std::vector<std::vector<std::string>> bad = {
      {},                                            // no command
      {"frobnicate"},                                // unknown command
      {"list", "--bogus"},                           // unknown flag
      {"--steps", "3", "list"},                      // a command flag before the command
      {"status"},                                    // missing ID
      {"status", "a", "b"},                          // extra argument
      {"list", "--json=1"},                          // a switch with a value
      {"list", "--timeout"},                         // missing value
      {"list", "--timeout", "0"},                    // not positive
      {"list", "--timeout", "abc"},                  // not a number
      {"run", "s-1", "--steps", "1", "--steps", "2"},  // given twice
      {"list", "-x"},                                // unknown short option
  };
  for (const auto& args : bad) EXPECT_THROW(parse(args), UsageError) << ::testing::PrintToString(args);
  EXPECT_THROW(submit_options(parse({"submit", "f"})), UsageError);                     // --steps required
  EXPECT_THROW(submit_options(parse({"submit", "f", "--steps", "0"})), UsageError);     // >= 1
  EXPECT_THROW(submit_options(parse({"submit", "f", "--steps", "12x"})), UsageError);   // whole text
  EXPECT_THROW(submit_options(parse({"submit", "f", "--steps", "9", "--profile-every", "0"})), UsageError);
  EXPECT_THROW(run_options(parse({"run", "s-1"})), UsageError);
  EXPECT_THROW(watch_options(parse({"watch", "s-1"})), UsageError);  // neither stream
  EXPECT_THROW(watch_options(parse({"watch", "s-1", "--profiles", "--particles"})), UsageError);
  EXPECT_THROW(watch_options(parse({"watch", "s-1", "--profiles", "--frames", "0"})), UsageError);
}

// `submit FILE` without --steps runs the steps the file's "# steps: N" line declares (the example
// scenarios each have one); --steps wins; a file that declares none needs --steps.
TEST(CliOptions, SubmitTakesTheStepsTheFileDeclares) {
  const auto steps = [](const std::string& text) {
    std::istringstream in(text);
    return declared_steps(in, "f");
  };
  EXPECT_EQ(steps("# A scenario.\n# steps: 1500 (18 bounces)\nname: \"x\"\n# steps: 9\n"), 1500);  // the first
  EXPECT_EQ(steps("  #steps:42\n"), 42);
  EXPECT_EQ(steps("name: \"x\"  # steps: 5 is not a comment line\n"), 0);
  EXPECT_EQ(steps("# stepsize: 3\n{\"name\": \"json\"}\n"), 0);
  for (const char* bad : {"# steps: lots\n", "# steps: 0\n", "# steps:\n", "# steps: 99999999999999999999\n"})
    EXPECT_THROW(steps(bad), UsageError) << bad;

  const auto dir = std::filesystem::temp_directory_path() / ("lbsolid-declared-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string with = (dir / "with.textproto").string(), without = (dir / "without.textproto").string();
  std::ofstream(with) << "# steps: 400 (why)\nname: \"x\"\n";
  std::ofstream(without) << "name: \"x\"\n";
  const SubmitOptions declared = submit_options(parse({"submit", with}));
  EXPECT_EQ(declared.steps, 400);
  EXPECT_EQ(declared.profile_every, 2);  // max(1, steps / 200) of the declared steps
  EXPECT_EQ(submit_options(parse({"submit", with, "--steps", "7"})).steps, 7);
  EXPECT_THROW(submit_options(parse({"submit", without})), UsageError);
  std::filesystem::remove_all(dir);
}

// --set may be given many times (each kept, in order); other flags still only once.
TEST(CliOptions, SetIsRepeatable) {
  const auto o = submit_options(parse({"submit", "f", "--set", "fluid.omega=1.2", "--steps", "5", "--set=domain.nx=8"}));
  EXPECT_EQ(o.overrides, (std::vector<std::string>{"fluid.omega=1.2", "domain.nx=8"}));
  EXPECT_EQ(parse({"validate", "f", "--set", "a=1", "--set", "b=2"}).all("set"), (std::vector<std::string>{"a=1", "b=2"}));
  EXPECT_TRUE(submit_options(parse({"submit", "f", "--steps", "5"})).overrides.empty());
  EXPECT_THROW(parse({"submit", "f", "--steps", "5", "--steps", "6"}), UsageError);
  EXPECT_THROW(parse({"status", "s-1", "--set", "a=1"}), UsageError);  // only submit and validate take it
}

TEST(CliOptions, DoubleDashEndsFlags) {
  const auto line = parse({"status", "--", "-odd-id"});
  ASSERT_EQ(line.positional.size(), 1u);
  EXPECT_EQ(line.positional[0], "-odd-id");
}

// --- exit codes ----------------------------------------------------------------------------------

TEST(ExitCodes, Mapping) {
  using grpc::StatusCode;
  EXPECT_EQ(exit_code_for(StatusCode::OK), 0);
  for (auto code : {StatusCode::INVALID_ARGUMENT, StatusCode::NOT_FOUND, StatusCode::ALREADY_EXISTS,
                    StatusCode::FAILED_PRECONDITION, StatusCode::OUT_OF_RANGE})
    EXPECT_EQ(exit_code_for(code), 2) << status_code_name(code);
  for (auto code : {StatusCode::UNAVAILABLE, StatusCode::DEADLINE_EXCEEDED, StatusCode::RESOURCE_EXHAUSTED,
                    StatusCode::ABORTED, StatusCode::INTERNAL, StatusCode::UNKNOWN})
    EXPECT_EQ(exit_code_for(code), 3) << status_code_name(code);
  EXPECT_EQ(status_code_name(StatusCode::FAILED_PRECONDITION), "FAILED_PRECONDITION");
}

// A request gRPC cannot parse comes back INTERNAL with no message, and a message over the size
// limit RESOURCE_EXHAUSTED: retrying the same call fails the same way, so an orchestrator must not.
TEST(ExitCodes, FailuresThatARetryCannotFixAreBadInput) {
  using grpc::StatusCode;
  EXPECT_EQ(exit_code_for(grpc::Status(StatusCode::INTERNAL, "")), 2);
  EXPECT_EQ(exit_code_for(grpc::Status(StatusCode::INTERNAL, "checkpoint: disk error")), 3);
  EXPECT_EQ(exit_code_for(grpc::Status(StatusCode::RESOURCE_EXHAUSTED,
                                       "Received message larger than max (5242880 vs. 4194304)")),
            2);
  EXPECT_EQ(exit_code_for(grpc::Status(StatusCode::RESOURCE_EXHAUSTED, "sessions: the daemon holds its limit")), 3);
}

// --- JSON and progress text ------------------------------------------------------------------------

// A fake DNS: names and their addresses; counts the questions.
struct FakeDns {
  std::map<std::string, std::vector<std::string>> names;
  int questions = 0;
  Resolver resolver() {
    return [this](const std::string& host) {
      ++questions;
      const auto it = names.find(host);
      return it == names.end() ? std::vector<std::string>{} : it->second;
    };
  }
};

TEST(DaemonNames, ANameOfSeveralAddressesIsThatManyDaemons) {
  FakeDns dns{{{"replicas.example", {"10.0.0.7", "10.0.0.8", "fd00::9"}}, {"one.example", {"10.0.0.1"}}}};
  const auto daemons = expand_dns_names({"replicas.example:50051", "one.example:443", "absent.example:1"}, dns.resolver());
  ASSERT_EQ(daemons.size(), 5u);
  EXPECT_EQ(daemons[0].target, "10.0.0.7:50051");
  EXPECT_EQ(daemons[1].target, "10.0.0.8:50051");
  EXPECT_EQ(daemons[2].target, "[fd00::9]:50051");
  for (int k = 0; k < 3; ++k) EXPECT_EQ(daemons[k].name, "replicas.example");
  // One address, or none: left to gRPC as listed (it resolves again when it dials, or reports it).
  EXPECT_EQ(daemons[3].target, "one.example:443");
  EXPECT_EQ(daemons[3].name, "");
  EXPECT_EQ(daemons[4].target, "absent.example:1");
  EXPECT_EQ(dns.questions, 3);
}

TEST(DaemonNames, SocketsLiteralsSchemesAndPortlessEntriesAreNotResolved) {
  FakeDns dns;
  const std::vector<std::string> entries = {"unix:/run/lbsolid.sock", "127.0.0.1:50051", "[::1]:50051",
                                            "dns:///replicas.example:50051", "ipv4:10.0.0.1:5", "nohostport"};
  const auto daemons = expand_dns_names(entries, dns.resolver());
  ASSERT_EQ(daemons.size(), entries.size());
  for (std::size_t k = 0; k < entries.size(); ++k) {
    EXPECT_EQ(daemons[k].target, entries[k]);
    EXPECT_EQ(daemons[k].name, "");
  }
  EXPECT_EQ(dns.questions, 0);
}

TEST(DaemonNames, TheSystemResolverGivesEachAddressOnce) {
  // getaddrinfo answers 127.0.0.1 once per socket type unless asked for one: SOCK_STREAM only.
  EXPECT_EQ(resolve_tcp("127.0.0.1"), std::vector<std::string>{"127.0.0.1"});
  EXPECT_TRUE(resolve_tcp("name.invalid").empty());  // RFC 6761: .invalid never resolves
}

TEST(JsonWriter, EscapesAndNumbers) {
  EXPECT_EQ(json_quote("a\"b\\c\n\x01"), "\"a\\\"b\\\\c\\n\\u0001\"");
  EXPECT_EQ(json_number(0.1), "0.1");
  EXPECT_EQ(json_number(1e300 * 1e300), "null");
  EXPECT_EQ(JsonObject().string("a", "x").integer("n", 1234567890123LL).boolean("b", false).str(),
            "{\"a\":\"x\",\"n\":1234567890123,\"b\":false}");
  EXPECT_EQ(json_array(std::vector<double>{1, 2.5}), "[1,2.5]");
}

TEST(ProgressText, LineAndBar) {
  EXPECT_EQ(format_duration(42), "42s");
  EXPECT_EQ(format_duration(187), "3m07s");
  EXPECT_EQ(format_duration(7500), "2h05m");
  EXPECT_EQ(format_duration(-1), "?");
  const ProgressSample p{1500, 15000, 3000, 8.06, 4.5};
  EXPECT_EQ(format_progress_line(p), "step 1500/15000 (10.0%)  3000 steps/s  8.06 MLUPS  ETA 5s");
  const std::string bar = format_progress_bar(p, 10);
  EXPECT_EQ(bar.substr(0, 13), "[#         ] ");
}

}  // namespace
}  // namespace lbsolid::cli
