#pragma once
// A minimal JSON object builder for the CLI's output: keys in insertion order, strings escaped,
// numbers in their shortest round-trip form (non-finite ones as null), 64-bit integers as numbers
// (protobuf's own JSON would quote them, which scripts then have to undo).
#include <string>
#include <string_view>
#include <vector>

namespace lbsolid::cli {

std::string json_quote(std::string_view text);
std::string json_number(double value);
std::string json_array(const std::vector<double>& values);
std::string json_array(const std::vector<std::string>& raw_items);  // items are JSON already
std::string json_string_array(const std::vector<std::string>& strings);

class JsonObject {
 public:
  JsonObject& string(std::string_view key, std::string_view value);
  JsonObject& integer(std::string_view key, long long value);
  JsonObject& number(std::string_view key, double value);
  JsonObject& boolean(std::string_view key, bool value);
  JsonObject& null(std::string_view key);
  JsonObject& raw(std::string_view key, std::string_view json);  // json must be valid JSON
  std::string str() const { return "{" + body_ + "}"; }

 private:
  void key(std::string_view key);
  std::string body_;
};

}  // namespace lbsolid::cli
