#pragma once
// Line and column for JSON scenario files. protobuf's JsonStringToMessage reports no position
// ("Unexpected token.", "bogus: Cannot find field."), so a scenario file's JSON is first walked
// here: a syntax error is reported where it is, and every object key's position is recorded so a
// later error about a field can point at that field's key. Internal to scenario_translation.cpp;
// header-only because the API library is a single translation unit.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace lbsolid::server::json {

struct KeyPosition {
  std::string path;  // dotted, array indices left out: "domain.nx", "bodies.size"
  int line = 1, column = 1;
};

class Locator {
 public:
  explicit Locator(std::string_view text) : text_(text) {}

  // True when the text is one well-formed JSON value; otherwise "line L column C: reason".
  bool check_syntax(std::string* error) {
    skip_blanks();
    if (!value("", 0)) {
      *error = error_;
      return false;
    }
    skip_blanks();
    if (i_ < text_.size()) {
      *error = at("unexpected text after the end of the scenario");
      return false;
    }
    return true;
  }

  // "line L column C" of the key at `path`, else of the last key whose own name is the last
  // component of `path`, else of the start of the text.
  std::string where(const std::string& path) const {
    const KeyPosition* found = nullptr;
    for (const auto& k : keys_)
      if (k.path == path) return position(k.line, k.column);
    const std::string name = path.substr(path.rfind('.') == std::string::npos ? 0 : path.rfind('.') + 1);
    for (const auto& k : keys_) {
      const std::size_t dot = k.path.rfind('.');
      if (k.path.compare(dot == std::string::npos ? 0 : dot + 1, std::string::npos, name) == 0) found = &k;
    }
    return found ? position(found->line, found->column) : position(first_line_, first_column_);
  }

 private:
  // Deeper than any scenario; stops a hostile file from exhausting the stack.
  static constexpr int kMaxDepth = 64;

  static std::string position(int line, int column) {
    return "line " + std::to_string(line) + " column " + std::to_string(column);
  }
  std::string at(const std::string& reason) const { return position(line_, column_) + ": " + reason; }
  bool fail(const std::string& reason) {
    error_ = at(reason);
    return false;
  }

  bool done() const { return i_ >= text_.size(); }
  char peek() const { return text_[i_]; }
  void advance() {
    if (text_[i_] == '\n') {
      ++line_;
      column_ = 1;
    } else {
      ++column_;
    }
    ++i_;
  }
  void skip_blanks() {
    while (!done() && (peek() == ' ' || peek() == '\t' || peek() == '\n' || peek() == '\r')) advance();
  }

  bool value(const std::string& path, int depth) {
    skip_blanks();
    if (done()) return fail("unexpected end of text, expected a value");
    if (depth == 0) {
      first_line_ = line_;
      first_column_ = column_;
    }
    if (depth > kMaxDepth) return fail("nested too deeply");
    const char c = peek();
    if (c == '{') return object(path, depth);
    if (c == '[') return array(path, depth);
    if (c == '"') return string(nullptr);
    if (c == '-' || digit()) return number();
    if (c >= 'a' && c <= 'z') {
      const std::size_t start = i_;
      const int line = line_, column = column_;
      while (!done() && peek() >= 'a' && peek() <= 'z') advance();
      const std::string_view word = text_.substr(start, i_ - start);
      if (word == "true" || word == "false" || word == "null") return true;
      line_ = line;
      column_ = column;
      return fail("unexpected '" + std::string(word) + "'; expected a value");
    }
    return fail(std::string("unexpected character '") + c + "'; expected a value");
  }

  bool object(const std::string& path, int depth) {
    advance();  // '{'
    skip_blanks();
    if (!done() && peek() == '}') {
      advance();
      return true;
    }
    for (;;) {
      skip_blanks();
      if (done() || peek() != '"') return fail("expected a quoted field name");
      KeyPosition key{"", line_, column_};
      std::string name;
      if (!string(&name)) return false;
      key.path = path.empty() ? name : path + "." + name;
      keys_.push_back(key);
      skip_blanks();
      if (done() || peek() != ':') return fail("expected ':' after the field name \"" + name + "\"");
      advance();
      if (!value(key.path, depth + 1)) return false;
      skip_blanks();
      if (!done() && peek() == ',') {
        advance();
        continue;
      }
      if (!done() && peek() == '}') {
        advance();
        return true;
      }
      return fail("expected ',' or '}' after the value of \"" + name + "\"");
    }
  }

  bool array(const std::string& path, int depth) {
    advance();  // '['
    skip_blanks();
    if (!done() && peek() == ']') {
      advance();
      return true;
    }
    for (;;) {
      if (!value(path, depth + 1)) return false;
      skip_blanks();
      if (!done() && peek() == ',') {
        advance();
        continue;
      }
      if (!done() && peek() == ']') {
        advance();
        return true;
      }
      return fail("expected ',' or ']' in a list");
    }
  }

  bool digit() const { return !done() && peek() >= '0' && peek() <= '9'; }
  bool digits() {
    if (!digit()) return fail("expected a digit");
    while (digit()) advance();
    return true;
  }

  // -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?, as JSON writes numbers.
  bool number() {
    if (peek() == '-') advance();
    if (!done() && peek() == '0') {
      advance();
    } else if (!digits()) {
      return false;
    }
    if (!done() && peek() == '.') {
      advance();
      if (!digits()) return false;
    }
    if (!done() && (peek() == 'e' || peek() == 'E')) {
      advance();
      if (!done() && (peek() == '+' || peek() == '-')) advance();
      if (!digits()) return false;
    }
    return true;
  }

  // A quoted string; escapes are skipped over, not decoded (field names need none).
  bool string(std::string* out) {
    advance();  // opening quote
    for (;;) {
      if (done() || peek() == '\n') return fail("unterminated string");
      const char c = peek();
      advance();
      if (c == '"') return true;
      if (c == '\\') {
        if (done()) return fail("unterminated string");
        advance();
      } else if (out) {
        out->push_back(c);
      }
    }
  }

  std::string_view text_;
  std::size_t i_ = 0;
  int line_ = 1, column_ = 1;
  int first_line_ = 1, first_column_ = 1;
  std::string error_;
  std::vector<KeyPosition> keys_;
};

}  // namespace lbsolid::server::json
