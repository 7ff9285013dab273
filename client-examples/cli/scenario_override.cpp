#include "scenario_override.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string_view>

#include "cli_error.h"
#include "exit_codes.h"

namespace lbsolid::cli {

namespace {

namespace pb = google::protobuf;

struct Segment {
  std::string name;
  std::optional<int> index;  // [i]
};

[[noreturn]] void refuse(const std::string& assignment, const std::string& reason) {
  throw CliError(kExitBadInput, "--set " + assignment + ": " + reason);
}

std::optional<Segment> parse_segment(std::string_view text) {
  Segment s;
  const auto open = text.find('[');
  s.name = std::string(text.substr(0, open));
  if (s.name.empty()) return std::nullopt;
  if (open == std::string_view::npos) return s;
  if (text.back() != ']') return std::nullopt;
  const std::string_view digits = text.substr(open + 1, text.size() - open - 2);
  int index = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
  if (digits.empty() || error != std::errc() || end != digits.data() + digits.size() || index < 0)
    return std::nullopt;
  s.index = index;
  return s;
}

template <class T>
std::optional<T> parse_integer(const std::string& text) {
  T value{};
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

std::optional<double> parse_real(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (*end != '\0' || !std::isfinite(value)) return std::nullopt;
  return value;
}

// Sets field (element `index` if repeated) of `message` from `text`; false when text does not fit.
bool set_scalar(pb::Message& message, const pb::FieldDescriptor& field, std::optional<int> index,
                const std::string& text) {
  const pb::Reflection& r = *message.GetReflection();
  const bool repeated = field.is_repeated();
  switch (field.cpp_type()) {
    case pb::FieldDescriptor::CPPTYPE_DOUBLE:
    case pb::FieldDescriptor::CPPTYPE_FLOAT: {
      const auto v = parse_real(text);
      if (!v) return false;
      if (field.cpp_type() == pb::FieldDescriptor::CPPTYPE_FLOAT) {
        if (std::abs(*v) > std::numeric_limits<float>::max()) return false;
        repeated ? r.SetRepeatedFloat(&message, &field, *index, static_cast<float>(*v))
                 : r.SetFloat(&message, &field, static_cast<float>(*v));
      } else {
        repeated ? r.SetRepeatedDouble(&message, &field, *index, *v) : r.SetDouble(&message, &field, *v);
      }
      return true;
    }
    case pb::FieldDescriptor::CPPTYPE_INT32: {
      const auto v = parse_integer<std::int32_t>(text);
      if (v) repeated ? r.SetRepeatedInt32(&message, &field, *index, *v) : r.SetInt32(&message, &field, *v);
      return v.has_value();
    }
    case pb::FieldDescriptor::CPPTYPE_INT64: {
      const auto v = parse_integer<std::int64_t>(text);
      if (v) repeated ? r.SetRepeatedInt64(&message, &field, *index, *v) : r.SetInt64(&message, &field, *v);
      return v.has_value();
    }
    case pb::FieldDescriptor::CPPTYPE_UINT32: {
      const auto v = parse_integer<std::uint32_t>(text);
      if (v) repeated ? r.SetRepeatedUInt32(&message, &field, *index, *v) : r.SetUInt32(&message, &field, *v);
      return v.has_value();
    }
    case pb::FieldDescriptor::CPPTYPE_UINT64: {
      const auto v = parse_integer<std::uint64_t>(text);
      if (v) repeated ? r.SetRepeatedUInt64(&message, &field, *index, *v) : r.SetUInt64(&message, &field, *v);
      return v.has_value();
    }
    case pb::FieldDescriptor::CPPTYPE_BOOL: {
      if (text != "true" && text != "false") return false;
      repeated ? r.SetRepeatedBool(&message, &field, *index, text == "true")
               : r.SetBool(&message, &field, text == "true");
      return true;
    }
    case pb::FieldDescriptor::CPPTYPE_STRING:
      repeated ? r.SetRepeatedString(&message, &field, *index, text) : r.SetString(&message, &field, text);
      return true;
    case pb::FieldDescriptor::CPPTYPE_ENUM: {
      const pb::EnumValueDescriptor* value = field.enum_type()->FindValueByName(text);
      if (!value) {
        const auto number = parse_integer<int>(text);
        if (number) value = field.enum_type()->FindValueByNumber(*number);
      }
      if (!value) return false;
      repeated ? r.SetRepeatedEnum(&message, &field, *index, value) : r.SetEnum(&message, &field, value);
      return true;
    }
    case pb::FieldDescriptor::CPPTYPE_MESSAGE: return false;
  }
  return false;
}

std::string type_name(const pb::FieldDescriptor& field) {
  if (field.cpp_type() == pb::FieldDescriptor::CPPTYPE_ENUM) {
    std::string names;
    for (int k = 0; k < field.enum_type()->value_count(); ++k)
      names += (k ? ", " : "") + field.enum_type()->value(k)->name();
    return "one of " + names;
  }
  if (field.cpp_type() == pb::FieldDescriptor::CPPTYPE_BOOL) return "true or false";
  if (field.cpp_type() == pb::FieldDescriptor::CPPTYPE_DOUBLE || field.cpp_type() == pb::FieldDescriptor::CPPTYPE_FLOAT)
    return "a finite number";
  return std::string("a ") + field.cpp_type_name();
}

}  // namespace

void apply_override(lbsolid::v1::Scenario& scenario, const std::string& assignment) {
  const auto equals = assignment.find('=');
  if (equals == std::string::npos) refuse(assignment, "expected PATH=VALUE");
  const std::string path = assignment.substr(0, equals), value = assignment.substr(equals + 1);
  pb::Message* message = &scenario;
  std::string_view rest = path, walked;
  while (true) {
    const auto dot = rest.find('.');
    const std::string_view text = rest.substr(0, dot);
    const auto segment = parse_segment(text);
    if (!segment) refuse(assignment, "'" + std::string(text) + "' is not a field name (with an optional [index])");
    const pb::Descriptor& type = *message->GetDescriptor();
    const pb::FieldDescriptor* field = type.FindFieldByName(segment->name);
    const std::string where = walked.empty() ? "the scenario" : "'" + std::string(walked) + "'";
    if (!field) refuse(assignment, where + " (" + type.name() + ") has no field '" + segment->name + "'");
    const pb::Reflection& r = *message->GetReflection();
    if (field->is_repeated() != segment->index.has_value())
      refuse(assignment, field->is_repeated() ? "'" + segment->name + "' is repeated: give an index, " + segment->name + "[0]"
                                              : "'" + segment->name + "' is not repeated: no index");
    if (field->is_repeated() && *segment->index >= r.FieldSize(*message, field))
      refuse(assignment, "'" + segment->name + "' has " + std::to_string(r.FieldSize(*message, field)) +
                             " entries; index " + std::to_string(*segment->index) + " is past its end");
    walked = std::string_view(path).substr(0, walked.size() + (walked.empty() ? 0 : 1) + text.size());
    const bool last = dot == std::string_view::npos;
    if (field->cpp_type() == pb::FieldDescriptor::CPPTYPE_MESSAGE) {
      if (last) refuse(assignment, "'" + path + "' is a message (" + field->message_type()->name() + "): name one of its fields");
      message = field->is_repeated() ? r.MutableRepeatedMessage(message, field, *segment->index)
                                     : r.MutableMessage(message, field);
      rest = rest.substr(dot + 1);
      continue;
    }
    if (!last) refuse(assignment, "'" + std::string(walked) + "' is a value, not a message");
    if (!set_scalar(*message, *field, segment->index, value))
      refuse(assignment, "'" + value + "' is not " + type_name(*field) + " (the type of " + path + ")");
    return;
  }
}

}  // namespace lbsolid::cli
