#pragma once
// Text a client sent (a scenario name, a request id, an error that echoes one) made safe for one
// log line: a name holding "\n2024-01-01 INFO ..." must not forge a line of its own. Header-only:
// the daemon's session, service and main code call it around every piece of such text they log.
#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace lbsolid::server {

// The size of the longest prefix of `text` of at most `max_bytes` that does not end inside a UTF-8
// character (at most 3 bytes are given back, so text that is not UTF-8 is still cut near max_bytes).
inline std::size_t utf8_prefix_size(std::string_view text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return text.size();
  std::size_t end = max_bytes;
  for (int back = 0; back < 3 && end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80; ++back) --end;
  return end;
}

namespace log_text_detail {

// The length of the well-formed UTF-8 character starting at text[i] (RFC 3629: no overlong forms,
// no surrogates, nothing above U+10FFFF) and its code point; 0 when the bytes there are not one.
inline std::size_t utf8_character(std::string_view text, std::size_t i, char32_t* code_point) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  std::size_t length;
  unsigned char low = 0x80, high = 0xBF;  // the range of the second byte
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;
    if (lead == 0xED) high = 0x9F;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;
    if (lead == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (i + length > text.size() || byte(i + 1) < low || byte(i + 1) > high) return 0;
  char32_t c = lead & (0x7F >> length);
  for (std::size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    c = (c << 6) | (byte(i + k) & 0x3F);
  }
  *code_point = c;
  return length;
}

}  // namespace log_text_detail

// `text` in double quotes, with \" and \\, \n \r \t, every other ASCII control character and every
// byte that is not part of well-formed UTF-8 as \xNN, and the C1 controls and U+2028/U+2029 (line
// breaks to some log viewers) as \uNNNN. Text longer than `max_bytes` is cut on a character
// boundary and followed by ...(N bytes), N its whole size: "abc"...(5000 bytes).
inline std::string log_text(std::string_view text, std::size_t max_bytes = 200) {
  const std::size_t shown = utf8_prefix_size(text, max_bytes);
  std::string out = "\"";
  out.reserve(shown + 2);
  char escape[16];
  for (std::size_t i = 0; i < shown;) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      switch (c) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\n': out += "\\n"; break;
        case '\r': out += "\\r"; break;
        case '\t': out += "\\t"; break;
        default:
          if (c < 0x20 || c == 0x7F) {
            std::snprintf(escape, sizeof escape, "\\x%02x", c);
            out += escape;
          } else {
            out += static_cast<char>(c);
          }
      }
      ++i;
      continue;
    }
    char32_t code_point = 0;
    const std::size_t length = log_text_detail::utf8_character(text.substr(0, shown), i, &code_point);
    if (length == 0) {
      std::snprintf(escape, sizeof escape, "\\x%02x", c);
      out += escape;
      ++i;
    } else if (code_point <= 0x9F || code_point == 0x2028 || code_point == 0x2029) {
      std::snprintf(escape, sizeof escape, "\\u%04x", static_cast<unsigned>(code_point));
      out += escape;
      i += length;
    } else {
      out.append(text.substr(i, length));
      i += length;
    }
  }
  out += '"';
  if (shown < text.size()) out += "...(" + std::to_string(text.size()) + " bytes)";
  return out;
}

}  // namespace lbsolid::server
